// Level 1 for a whole render region at once (ours; the paper traces per tile): every
// corner the region's tiles read is traced exactly once, in blocks that do not follow the
// tile grid, and each tile then gathers its corner grid from the field before levels 2-3.
//
// Per tile (trace_corners), a 64² tile traces a 65² grid (the corners it shares with its
// neighbours, traced again by them: the paper's one-pixel overlap), with the curvature
// correction a 67² grid, and the odd side pads its 2x2 packets to 68²: 1.13 camera rays
// per pixel before any refinement, against 1.00 here. Corners are pure functions of their
// positions, so the image is bit-identical to the per-tile path, for any block or tile
// size, thread count or order. Memory: 36 bytes per corner, plus the source's probe when
// the hidden-detail flags are on (SurfaceProbe, 76 bytes): 117 MB at 1024²; callers fall
// back to the per-tile path above a budget (corner_field_bytes).
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "aa/adaptive_sampler.h"

namespace zz {

// Corners (x, y), x in [x0, x0 + width), y in [y0, y0 + height), frame pixel positions.
struct CornerRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  size_t count() const { return size_t(width) * size_t(height); }
};

// The corners every tile of `region` reads (corner_layout of each, united): the pixel
// corners of the region grown by the filter's margin (clipped to the frame), plus the
// curvature ring.
inline CornerRect corner_field_rect(const TileRect& region, int frame_width, int frame_height,
                                    const AdaptiveSettings& settings) {
  TileTarget whole;
  whole.rect = region;
  whole.frame_width = frame_width;
  whole.frame_height = frame_height;
  const CornerLayout l = corner_layout(whole, settings);
  return {l.x0, l.y0, l.width, l.height};
}

// Bytes a field over `rect` takes for a source of `S` under `settings`.
template <SampleSource S>
size_t corner_field_bytes(const CornerRect& rect, const AdaptiveSettings& settings) {
  size_t per_corner = 2 * sizeof(float4) + sizeof(int32_t);
  if (flags_hidden<S>(settings)) per_corner += sizeof(typename ProbeOf<S>::type);
  return rect.count() * per_corner;
}

template <class Probe>
struct CornerField {
  CornerRect rect;
  std::vector<float4> linear;      // AoS (r, g, b, 0)
  std::vector<float4> display;     // tone-mapped
  std::vector<int32_t> signature;  // signature.h
  std::vector<Probe> probes;       // empty unless the hidden-detail flags are on

  CornerField(const CornerRect& r, bool with_probes)
      : rect(r), linear(r.count()), display(r.count()), signature(r.count()), probes(with_probes ? r.count() : 0) {}
  size_t index(int x, int y) const { return size_t(y - rect.y0) * size_t(rect.width) + size_t(x - rect.x0); }

  // The field cut into blocks of about `size`² corners (even sides, so only the field's own
  // odd last row or column pads a packet), to trace in parallel.
  std::vector<CornerRect> blocks(int size) const {
    std::vector<CornerRect> out;
    for (int y = 0; y < rect.height; y += size)
      for (int x = 0; x < rect.width; x += size)
        out.push_back({rect.x0 + x, rect.y0 + y, std::min(size, rect.width - x), std::min(size, rect.height - y)});
    return out;
  }
};

template <SampleSource S>
using CornerFieldOf = CornerField<typename ProbeOf<S>::type>;

// Level 1 of one block of the field.
template <SampleSource S>
void trace_field_block(S& source, const AdaptiveSettings& settings, const CornerRect& block,
                       CornerFieldOf<S>& field, AaStats& stats) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  const size_t first = field.index(block.x0, block.y0);
  trace_corner_block(source, settings.tonemap, block.x0, block.y0, block.width, block.height,
                     size_t(field.rect.width), field.linear.data() + first, field.display.data() + first,
                     field.signature.data() + first, field.probes.empty() ? nullptr : field.probes.data() + first,
                     stats);
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

// A tile's corner grid (and its hidden-detail flags) from the field, as trace_corners
// would have traced it; no rays.
template <SampleSource S>
void gather_corners(S& source, const CornerFieldOf<S>& field, const TileTarget& target,
                    const AdaptiveSettings& settings, CornerGrid& grid, AaStats& stats) {
  if (target.rect.width() <= 0 || target.rect.height() <= 0) return;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  const CornerLayout layout = corner_layout(target, settings);
  const bool probing = flags_hidden<S>(settings);
  grid.reserve(layout.corners(), probing ? layout.pixels() : 0);
  using Probe = typename ProbeOf<S>::type;
  Probe* probes = probing ? corner_probes<Probe>(layout.corners()) : nullptr;
  for (int j = 0; j < layout.height; ++j) {
    const size_t from = field.index(layout.x0, layout.y0 + j), to = size_t(j) * size_t(layout.width);
    std::copy_n(field.linear.begin() + from, layout.width, grid.linear.begin() + to);
    std::copy_n(field.display.begin() + from, layout.width, grid.display.begin() + to);
    std::copy_n(field.signature.begin() + from, layout.width, grid.signature.begin() + to);
    if (probing) std::copy_n(field.probes.begin() + from, layout.width, probes + to);
  }
  if constexpr (HiddenDetailSource<S>) {
    if (probing) flag_hidden_pixels(source, layout, probes, settings, grid);
  }
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace zz
