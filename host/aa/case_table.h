// Level-1 case table (ALGORITHM.md §4): the 4-bit mask of corner discontinuities
// a0=d(A,B) a1=d(C,D) a2=d(A,C) a3=d(B,D) (bit i = a_i) -> none / horizontal / vertical.
// Built once from the rule text so the table and the rule cannot disagree.
#pragma once

#include <array>
#include <cstdint>

namespace zz {

enum class PixelCase : uint8_t { None = 0, Horizontal = 1, Vertical = 2 };

// The rule's first two clauses: horizontal if (!a2 or !a3) and (a0 and a1), else vertical if
// (!a0 or !a1) and (a2 and a3); None where neither decides.
constexpr PixelCase decided_orientation(int mask) {
  const bool a0 = mask & 1, a1 = mask & 2, a2 = mask & 4, a3 = mask & 8;
  if ((!a2 || !a3) && (a0 && a1)) return PixelCase::Horizontal;
  if ((!a0 || !a1) && (a2 && a3)) return PixelCase::Vertical;
  return PixelCase::None;
}

// The whole rule: else horizontal if any of a0..a3; else none.
constexpr PixelCase classify_corners(int mask) {
  const PixelCase decided = decided_orientation(mask);
  if (decided != PixelCase::None) return decided;
  return (mask & 0xF) ? PixelCase::Horizontal : PixelCase::None;
}

// Whether the first two clauses leave the orientation open (a corner cut off, two
// adjacent corners apart, all four sides, or no case): the paper then takes horizontal, a
// guess that a pixel the visibility map flags replaces by the way its edge runs
// (decide_level1 in adaptive_pixel.h).
constexpr bool orientation_open(int mask) { return decided_orientation(mask) == PixelCase::None; }

constexpr std::array<PixelCase, 16> make_case_table() {
  std::array<PixelCase, 16> t{};
  for (int m = 0; m < 16; ++m) t[m] = classify_corners(m);
  return t;
}

inline constexpr std::array<PixelCase, 16> kCaseTable = make_case_table();

}  // namespace zz
