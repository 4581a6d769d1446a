// The 25-point rank-1 lattice of a pixel (ALGORITHM.md §3):
//   P_k = (k/25, (7k mod 25)/25), k = 0..24.
// Every column and row of step 0.04 holds one point; the set maps onto itself under
// 90 and 180 degree rotations. k = 0 is corner A. The fully refined "25 rays per pixel"
// pattern is these 25 points with the four corners weighing 1/4 each.
#pragma once

#include <array>

namespace zz {

inline constexpr int kLatticePoints = 25;

struct LatticePoint {
  float u, v;
};

constexpr LatticePoint lattice_point(int k) {
  return {float(k) / 25.0f, float((7 * k) % 25) / 25.0f};
}

constexpr std::array<LatticePoint, kLatticePoints> make_lattice() {
  std::array<LatticePoint, kLatticePoints> p{};
  for (int k = 0; k < kLatticePoints; ++k) p[k] = lattice_point(k);
  return p;
}

inline constexpr std::array<LatticePoint, kLatticePoints> kLattice = make_lattice();

}  // namespace zz
