// Level-1 case table (ALGORITHM.md §4): the 4-bit mask of corner discontinuities
// a0=d(A,B) a1=d(C,D) a2=d(A,C) a3=d(B,D) (bit i = a_i) -> none / horizontal / vertical.
// Built once from the rule text so the table and the rule cannot disagree.
#pragma once

#include <array>
#include <cstdint>

namespace zz {

enum class PixelCase : uint8_t { None = 0, Horizontal = 1, Vertical = 2 };

constexpr PixelCase classify_corners(int mask) {
  const bool a0 = mask & 1, a1 = mask & 2, a2 = mask & 4, a3 = mask & 8;
  if ((!a2 || !a3) && (a0 && a1)) return PixelCase::Horizontal;
  if ((!a0 || !a1) && (a2 && a3)) return PixelCase::Vertical;
  if (a0 || a1 || a2 || a3) return PixelCase::Horizontal;
  return PixelCase::None;
}

constexpr std::array<PixelCase, 16> make_case_table() {
  std::array<PixelCase, 16> t{};
  for (int m = 0; m < 16; ++m) t[m] = classify_corners(m);
  return t;
}

inline constexpr std::array<PixelCase, 16> kCaseTable = make_case_table();

}  // namespace zz
