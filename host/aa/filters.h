// Reconstruction filters as a stage after levels 1–3 (ALGORITHM.md §8). The box filter is
// per pixel (corner_mean, curvature_corrected, box_lattice in adaptive_pixel.h); the
// Mitchell–Netravali filter (B = C = 1/3, radius 2) needs the lattices of the neighbours
// too, so the sampler leaves a region's samples (its tile grown by the filter's margin) and
// this stage filters the tile's own pixels from them. Not a template: one copy, whatever
// the sample source.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/simd.h"
#include "core/tile.h"

namespace zz {

// What levels 1–3 leave for the filter over `region` (frame pixels): the linear corner
// samples (corner (x, y) at corners[(y - corner_y0) * corner_stride + (x - corner_x0)]),
// and per region pixel (row-major over `region`) whether it was refined and, if so, its 25
// lattice values by physical k (k = 0 its top-left corner).
struct SampledRegion {
  TileRect region;
  const float4* corners = nullptr;
  int corner_x0 = 0, corner_y0 = 0, corner_stride = 0;
  const uint8_t* refined = nullptr;
  const float4* lattice = nullptr;

  int corner_index(int x, int y) const { return (y - corner_y0) * corner_stride + (x - corner_x0); }
  size_t pixel_index(int x, int y) const {
    return size_t(y - region.y0) * size_t(region.width()) + size_t(x - region.x0);
  }
};

// The Mitchell–Netravali filter over every lattice point of the pixels within 2 of each of
// the target tile's pixels (points of unrefined pixels: the bilinear interpolation of their
// corners), normalised by the weights' sum, the output clamped at 0 (never the weights).
// `samples.region` must hold the tile grown by kMitchellRadius, clipped to the frame.
void mitchell_filter(const SampledRegion& samples, const TileTarget& target);

}  // namespace zz
