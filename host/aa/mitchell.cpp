#include "aa/mitchell.h"

#include <cmath>

#include "aa/lattice.h"

namespace zz {

double mitchell1d(double x) {
  constexpr double B = 1.0 / 3.0, C = 1.0 / 3.0;
  x = std::fabs(x);
  if (x < 1.0)
    return ((12 - 9 * B - 6 * C) * x * x * x + (-18 + 12 * B + 6 * C) * x * x + (6 - 2 * B)) / 6.0;
  if (x < 2.0)
    return ((-B - 6 * C) * x * x * x + (6 * B + 30 * C) * x * x + (-12 * B - 48 * C) * x + (8 * B + 24 * C)) /
           6.0;
  return 0.0;
}

namespace {

MitchellLatticeWeights make_weights() {
  MitchellLatticeWeights w{};
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      double corner[4] = {0, 0, 0, 0}, sum = 0;
      for (int k = 0; k < kLatticePoints; ++k) {
        // Exact lattice coordinates (not the float ones) so the table is exact to float.
        const double u = k / 25.0, v = ((7 * k) % 25) / 25.0;
        const double wk = mitchell1d(dx + u - 0.5) * mitchell1d(dy + v - 0.5);
        w.point[dy + 2][dx + 2][k] = float(wk);
        if (float(wk) != 0.0f) w.nonzero_k[dy + 2][dx + 2][w.nonzero_count[dy + 2][dx + 2]++] = uint8_t(k);
        sum += wk;
        corner[0] += wk * (1 - u) * (1 - v);
        corner[1] += wk * u * (1 - v);
        corner[2] += wk * (1 - u) * v;
        corner[3] += wk * u * v;
      }
      for (int c = 0; c < 4; ++c) w.corner[dy + 2][dx + 2][c] = float(corner[c]);
      w.sum[dy + 2][dx + 2] = float(sum);
    }
  return w;
}

}  // namespace

const MitchellLatticeWeights& mitchell_lattice_weights() {
  static const MitchellLatticeWeights w = make_weights();
  return w;
}

}  // namespace zz
