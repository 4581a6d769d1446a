#include "aa/filters.h"

#include "aa/lattice.h"
#include "aa/mitchell.h"

namespace zz {

void mitchell_filter(const SampledRegion& s, const TileTarget& target) {
  const int W = target.frame_width, H = target.frame_height;
  const int cw = s.corner_stride;
  // Fixed summation order per output pixel (neighbours row by row, points in k order,
  // four interleaved accumulators to shorten the add chain), so the result depends only
  // on the pixel, never on the tiling.
  const MitchellLatticeWeights& mw = mitchell_lattice_weights();
  for (int y = target.rect.y0; y < target.rect.y1; ++y)
    for (int x = target.rect.x0; x < target.rect.x1; ++x) {
      float4 acc0(0.0f), acc1(0.0f), acc2(0.0f), acc3(0.0f);
      float wsum = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        const int qy = y + dy;
        if (qy < 0 || qy > H) continue;
        for (int dx = -2; dx <= 2; ++dx) {
          const int qx = x + dx;
          if (qx < 0 || qx > W) continue;
          const int ci = s.corner_index(qx, qy);
          const float* w = mw.point[dy + 2][dx + 2];
          if (qx == W || qy == H) {  // the frame's corner ring: only point k = 0 exists
            acc0 += s.corners[ci] * float4(w[0]);
            wsum += w[0];
            continue;
          }
          const size_t pi = s.pixel_index(qx, qy);
          if (s.refined[pi]) {
            const float4* lat = &s.lattice[pi * kLatticePoints];
            const uint8_t* nk = mw.nonzero_k[dy + 2][dx + 2];
            const int n = mw.nonzero_count[dy + 2][dx + 2];
            int j = 0;
            for (; j + 3 < n; j += 4) {
              acc0 += lat[nk[j]] * float4(w[nk[j]]);
              acc1 += lat[nk[j + 1]] * float4(w[nk[j + 1]]);
              acc2 += lat[nk[j + 2]] * float4(w[nk[j + 2]]);
              acc3 += lat[nk[j + 3]] * float4(w[nk[j + 3]]);
            }
            for (; j < n; ++j) acc0 += lat[nk[j]] * float4(w[nk[j]]);
          } else {
            const float* c = mw.corner[dy + 2][dx + 2];
            acc0 += s.corners[ci] * float4(c[0]);
            acc1 += s.corners[ci + 1] * float4(c[1]);
            acc2 += s.corners[ci + cw] * float4(c[2]);
            acc3 += s.corners[ci + cw + 1] * float4(c[3]);
          }
          wsum += mw.sum[dy + 2][dx + 2];
        }
      }
      // Negative lobes: clamp the output, never the weights (§8).
      alignas(16) float v[4];
      max(((acc0 + acc1) + (acc2 + acc3)) / float4(wsum), float4(0.0f)).store(v);
      target.pixel(x, y) = glm::vec3(v[0], v[1], v[2]);
    }
}

}  // namespace zz
