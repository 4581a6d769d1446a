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
// the hidden-detail flags are on (the renderer's: three SurfaceProbes, the hit and what
// it shows by reflection and refraction, 228 bytes): 277 MB at 1024². Callers keep the
// per-tile path above kCornerFieldBudget (with probes, frames beyond about 4 million
// corners: 2560 x 1440 fits, 4K does not).
#pragma once

#include <cassert>
#include <chrono>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include "aa/adaptive_sampler.h"

namespace zz {

// Largest field the callers allocate; larger frames trace their corners per tile.
inline constexpr size_t kCornerFieldBudget = size_t(1) << 30;
// Corners per side of a block traced as one task (even: only the field's own odd last row
// or column pads a packet).
inline constexpr int kCornerBlock = 64;

// Corners (x, y), x in [x0, x0 + width), y in [y0, y0 + height), frame pixel positions.
struct CornerRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  size_t count() const { return size_t(width) * size_t(height); }
  bool contains(int x, int y) const { return x >= x0 && x < x0 + width && y >= y0 && y < y0 + height; }
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

// `rect` cut into blocks of `size`² corners (the last row and column of blocks smaller),
// to trace in parallel.
inline std::vector<CornerRect> corner_blocks(const CornerRect& rect, int size = kCornerBlock) {
  assert(size > 0 && size % 2 == 0);
  std::vector<CornerRect> out;
  for (int y = 0; y < rect.height; y += size)
    for (int x = 0; x < rect.width; x += size)
      out.push_back({rect.x0 + x, rect.y0 + y, std::min(size, rect.width - x), std::min(size, rect.height - y)});
  return out;
}

template <class Probe>
struct CornerField {
  CornerRect rect;
  // Left uninitialised (every entry is traced before it is read): a 1024² field is 40 MB
  // of corners, and 240 MB of the renderer's probes, that filling would write once more,
  // on one thread (the probes' default member values took 0.1 s of a 0.7 s room frame).
  std::unique_ptr<float4[]> linear;      // AoS (r, g, b, 0)
  std::unique_ptr<float4[]> display;     // tone-mapped
  std::unique_ptr<int32_t[]> signature;  // signature.h
  // Null unless the hidden-detail flags are on. Raw storage: probes are aggregates of
  // floats and integers (implicit-lifetime types), each written whole before it is read.
  std::unique_ptr<Probe[], void (*)(void*)> probes{nullptr, std::free};
  static_assert(std::is_trivially_copyable_v<Probe> && std::is_trivially_destructible_v<Probe>);

  CornerField(const CornerRect& r, bool with_probes)
      : rect(r),
        linear(std::make_unique_for_overwrite<float4[]>(r.count())),
        display(std::make_unique_for_overwrite<float4[]>(r.count())),
        signature(std::make_unique_for_overwrite<int32_t[]>(r.count())) {
    if (with_probes) {
      probes.reset(static_cast<Probe*>(std::malloc(r.count() * sizeof(Probe))));
      if (!probes) throw std::bad_alloc();
    }
  }

  static size_t bytes(const CornerRect& r, bool with_probes) {
    return r.count() * (2 * sizeof(float4) + sizeof(int32_t) + (with_probes ? sizeof(Probe) : 0));
  }
  size_t index(int x, int y) const {
    assert(rect.contains(x, y));
    return size_t(y - rect.y0) * size_t(rect.width) + size_t(x - rect.x0);
  }
};

template <SampleSource S>
using CornerFieldOf = CornerField<typename ProbeOf<S>::type>;

// Whether a region gets a field, and what it takes: its corners and bytes, or nothing
// when the region is empty or the field would exceed kCornerFieldBudget (the caller then
// traces per tile).
struct CornerFieldShape {
  CornerRect rect;
  size_t bytes = 0;
  bool fits() const { return bytes > 0; }
};
template <SampleSource S>
CornerFieldShape corner_field_shape(const TileRect& region, int frame_width, int frame_height,
                                    const AdaptiveSettings& settings) {
  const CornerRect rect = corner_field_rect(region, frame_width, frame_height, settings);
  const size_t bytes = CornerFieldOf<S>::bytes(rect, flags_hidden<S>(settings));
  if (region.empty() || bytes > kCornerFieldBudget) return {};
  return {rect, bytes};
}

// The field a frame region of a source of `S` under `settings` traces, or null (see
// corner_field_shape).
template <SampleSource S>
std::unique_ptr<CornerFieldOf<S>> make_corner_field(const TileRect& region, int frame_width, int frame_height,
                                                    const AdaptiveSettings& settings) {
  const CornerFieldShape shape = corner_field_shape<S>(region, frame_width, frame_height, settings);
  if (!shape.fits()) return nullptr;
  return std::make_unique<CornerFieldOf<S>>(shape.rect, flags_hidden<S>(settings));
}

// Level 1 of one block of the field.
template <SampleSource S>
void trace_field_block(S& source, const AdaptiveSettings& settings, const CornerRect& block,
                       CornerFieldOf<S>& field, AaStats& stats) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  const size_t first = field.index(block.x0, block.y0);
  trace_corner_block(source, settings.tonemap, block.x0, block.y0, block.width, block.height,
                     size_t(field.rect.width), field.linear.get() + first, field.display.get() + first,
                     field.signature.get() + first, field.probes ? field.probes.get() + first : nullptr,
                     stats);
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

// What the field's corners beyond `region`'s own pixel corners cost (the curvature ring,
// the Mitchell margin), in AaStats::margin_rays.
inline uint64_t field_margin_corners(const CornerRect& rect, const TileRect& region) {
  return rect.count() - own_corners(region);
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
  assert(field.rect.contains(layout.x0, layout.y0) &&
         field.rect.contains(layout.x0 + layout.width - 1, layout.y0 + layout.height - 1));
  const bool probing = flags_hidden<S>(settings);
  grid.reserve(layout.corners(), probing ? layout.pixels() : 0);
  for (int j = 0; j < layout.height; ++j) {
    const size_t from = field.index(layout.x0, layout.y0 + j), to = size_t(j) * size_t(layout.width);
    std::copy_n(field.linear.get() + from, layout.width, grid.linear.begin() + to);
    std::copy_n(field.display.get() + from, layout.width, grid.display.begin() + to);
    std::copy_n(field.signature.get() + from, layout.width, grid.signature.begin() + to);
  }
  if constexpr (HiddenDetailSource<S>) {
    // The probes are read in place: a tile's are ~1 MB, the colours a tenth of that.
    if (probing)
      flag_hidden_pixels(source, layout, field.probes.get() + field.index(layout.x0, layout.y0), field.rect.width,
                         settings, grid);
  }
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace zz
