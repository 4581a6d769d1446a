// Mitchell–Netravali reconstruction filter, B = C = 1/3, radius 2 pixels (ALGORITHM.md §8;
// Mitchell & Netravali 1988, eq. 8), with its weights precomputed over the 25-point
// lattice of a pixel and its 5x5 neighbours.
#pragma once

#include <cstdint>

namespace zz {

inline constexpr int kMitchellRadius = 2;

// 1D filter, x in pixels; zero for |x| >= 2. Separable: w(x, y) = m(x) m(y).
double mitchell1d(double x);

// Weights of the lattice points of neighbour pixel q = p + (dx, dy), dx, dy in [-2, 2],
// as seen from the centre of output pixel p. Index [dy + 2][dx + 2].
struct MitchellLatticeWeights {
  float point[5][5][25];   // by physical lattice index k (k = 0 is q's corner A)
  // Unrefined q: its points are the bilinear interpolation of its corners, so their
  // weights fold into 4 corner weights (TL, TR, BL, BR).
  float corner[5][5][4];
  float sum[5][5];         // sum of point[..][..][k] over all 25 k
  // Sparse form for the filter loop: the points with a nonzero weight, in k order.
  int nonzero_count[5][5];
  uint8_t nonzero_k[5][5][25];
};

const MitchellLatticeWeights& mitchell_lattice_weights();

}  // namespace zz
