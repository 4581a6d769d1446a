// Level 1 for a whole render region at once (ours; the paper traces per tile): every
// corner the region's tiles read is traced exactly once, in blocks that do not follow the
// tile grid, and each tile then gathers its corner grid from the field before levels 2-3.
//
// Per tile (trace_corners), a 64² tile traces a 65² grid (the corners it shares with its
// neighbours, traced again by them: the paper's one-pixel overlap), with the curvature
// correction a 67² grid, and the odd side pads its 2x2 packets to 68²: 1.13 camera rays
// per pixel before any refinement, against 1.00 here. Corners are pure functions of their
// positions, so the image is bit-identical to the per-tile path, for any block or tile
// size, thread count or order. Memory: 36 bytes per corner.
//
// The hidden-detail flags (hidden_detail.h) read each pixel's 4 x 4 stencil of probes (the
// renderer's are 864 bytes a corner: 900 MB for a 1024² frame, whose page faults and
// memory traffic once cost more than the flags' arithmetic). So the probes never make a
// frame-wide array: a block keeps its own in a per-thread buffer (4 MB) and
// flags its pixels whose stencil lies inside it at once; the probes within kBandHalf of a
// block boundary are copied to bands (about 19 % of the corners), from which the pixels
// whose stencil straddles blocks are flagged once every block is traced
// (flag_field_border). The field keeps one flag word per pixel (HiddenFlag). Callers keep the per-tile
// path above kCornerFieldBudget.
#pragma once

#include <algorithm>
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
inline constexpr size_t kCornerFieldBudget = size_t(2) << 30;  // 2 GiB: a 4k frame with every flag and the footprint takes 1.8 GB
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

// A pixel's stencil reaches one corner before its TL corner and two after: the pixels
// within 3 of a block boundary read corners of both blocks, and read no further than 3
// corners across it.
inline constexpr int kBandHalf = 3;

// Uninitialised storage for n trivially copyable T (every entry is written before it is
// read): a 1024² field's 40 MB of corners would otherwise be filled twice, on one thread.
template <class T>
using RawArray = std::unique_ptr<T[], void (*)(void*)>;
template <class T>
RawArray<T> make_raw_array(size_t n) {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  RawArray<T> a(static_cast<T*>(std::malloc(std::max<size_t>(1, n) * sizeof(T))), std::free);
  if (!a) throw std::bad_alloc();
  return a;
}

template <class Probe>
struct CornerField {
  CornerRect rect;
  RawArray<float4> linear{nullptr, std::free};      // AoS (r, g, b, 0)
  RawArray<float4> display{nullptr, std::free};     // tone-mapped
  RawArray<int32_t> signature{nullptr, std::free};  // signature.h
  // Null unless the hidden-detail flags are on: per pixel, at its TL corner's index, its
  // flag; and the probes of the boundary bands. Column band c (boundary x = kCornerBlock c
  // from rect.x0, c >= 1) holds columns [x - kBandHalf, x + kBandHalf) of every row, row
  // pitch 2 kBandHalf; row band r the rows [y - kBandHalf, y + kBandHalf) of every column.
  RawArray<HiddenFlag> hidden{nullptr, std::free};
  RawArray<Probe> column_bands{nullptr, std::free}, row_bands{nullptr, std::free};
  // Null unless unrefined pixels take the footprint delta: per pixel, like `hidden`.
  RawArray<float4> footprint{nullptr, std::free};

  CornerField(const CornerRect& r, bool with_probes, bool with_footprint = false)
      : rect(r),
        linear(make_raw_array<float4>(r.count())),
        display(make_raw_array<float4>(r.count())),
        signature(make_raw_array<int32_t>(r.count())) {
    if (with_probes) {
      // Zeroed: the pixels on the field's rim have no stencil and are never flagged (with
      // no ring beyond the frame, the frame's own outermost pixels), and must not read
      // what a previous frame left in the memory.
      hidden = make_raw_array<HiddenFlag>(r.count());
      std::fill_n(hidden.get(), r.count(), HiddenFlag{0});
      column_bands = make_raw_array<Probe>(column_band_size(r) * size_t(blocks_across(r.width) - 1));
      row_bands = make_raw_array<Probe>(row_band_size(r) * size_t(blocks_across(r.height) - 1));
      if (with_footprint) {
        footprint = make_raw_array<float4>(r.count());
        std::fill_n(footprint.get(), r.count(), float4(0.0f));
      }
    }
  }
  float4* footprint_at(size_t i) const { return footprint ? footprint.get() + i : nullptr; }
  CornerView corners(size_t i) const {
    return {linear.get() + i, display.get() + i, signature.get() + i, ptrdiff_t(rect.width)};
  }

  static int blocks_across(int corners) { return (corners + kCornerBlock - 1) / kCornerBlock; }
  static size_t column_band_size(const CornerRect& r) { return size_t(r.height) * 2 * kBandHalf; }
  static size_t row_band_size(const CornerRect& r) { return size_t(r.width) * 2 * kBandHalf; }
  static size_t bytes(const CornerRect& r, bool with_probes, bool with_footprint = false) {
    size_t b = r.count() * (2 * sizeof(float4) + sizeof(int32_t));
    if (with_probes)
      b += r.count() * (sizeof(HiddenFlag) + (with_footprint ? sizeof(float4) : 0)) +
           sizeof(Probe) * (column_band_size(r) * size_t(blocks_across(r.width) - 1) +
                            row_band_size(r) * size_t(blocks_across(r.height) - 1));
    return b;
  }
  size_t index(int x, int y) const {
    assert(rect.contains(x, y));
    return size_t(y - rect.y0) * size_t(rect.width) + size_t(x - rect.x0);
  }
  // Band entries of the corner at grid offsets (gx, gy) from rect's origin.
  Probe& in_column_band(int c, int gx, int gy) const {
    return column_bands[size_t(c - 1) * column_band_size(rect) + size_t(gy) * 2 * kBandHalf +
                        size_t(gx - (c * kCornerBlock - kBandHalf))];
  }
  Probe& in_row_band(int r, int gx, int gy) const {
    return row_bands[size_t(r - 1) * row_band_size(rect) + size_t(gy - (r * kCornerBlock - kBandHalf)) * rect.width +
                     size_t(gx)];
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
  const size_t bytes = CornerFieldOf<S>::bytes(rect, flags_hidden<S>(settings), corrects_footprint<S>(settings));
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
  return std::make_unique<CornerFieldOf<S>>(shape.rect, flags_hidden<S>(settings), corrects_footprint<S>(settings));
}

// Grid offsets [lo, hi) of block boundary k's band (k * kCornerBlock +- kBandHalf), within
// [0, n) and the block [b0, b1).
inline void band_span(int k, int b0, int b1, int n, int& lo, int& hi) {
  lo = std::max(k * kCornerBlock - kBandHalf, b0);
  hi = std::min({k * kCornerBlock + kBandHalf, b1, n});
}

// Along one axis of a grid n corners long, the pixels (by their TL corner's offset) whose
// stencil lies inside the block starting at offset b0: [b0 + 1, b0 + size - 3], size the
// block's (kCornerBlock, or less for the last block). The others are its band pixels.
struct InteriorPixels {
  int first, last;  // inclusive; empty when last < first
  int count() const { return std::max(0, last - first + 1); }
};
inline InteriorPixels interior_pixels(int b0, int n) {
  return {b0 + 1, b0 + std::min(kCornerBlock, n - b0) - 3};
}

// Level 1 of one block of the field; with the hidden-detail flags, the flags of the block's
// pixels whose stencil it holds, and its share of the bands.
template <SampleSource S>
void trace_field_block(S& source, const AdaptiveSettings& settings, const CornerRect& block,
                       CornerFieldOf<S>& field, AaStats& stats) {
  using Clock = std::chrono::steady_clock;
  using Probe = typename ProbeOf<S>::type;
  const Clock::time_point t0 = Clock::now();
  const size_t first = field.index(block.x0, block.y0);
  const int bx = block.x0 - field.rect.x0, by = block.y0 - field.rect.y0, bw = block.width, bh = block.height;
  assert(bx % kCornerBlock == 0 && by % kCornerBlock == 0 && bw <= kCornerBlock && bh <= kCornerBlock);
  Probe* probes = field.hidden ? corner_probes<Probe>(block.count()) : nullptr;
  trace_corner_block(source, settings.tonemap, block.x0, block.y0, bw, bh, size_t(field.rect.width),
                     field.linear.get() + first, field.display.get() + first, field.signature.get() + first, probes,
                     size_t(bw), stats);
  if constexpr (HiddenDetailSource<S>) {
    if (probes) {
      const int width = field.rect.width, height = field.rect.height;
      for (int c = bx / kCornerBlock; c <= bx / kCornerBlock + 1; ++c) {
        if (c < 1 || c >= field.blocks_across(width)) continue;
        int lo, hi;
        band_span(c, bx, bx + bw, width, lo, hi);
        for (int y = 0; y < bh; ++y)
          for (int x = lo; x < hi; ++x) field.in_column_band(c, x, by + y) = probes[y * bw + (x - bx)];
      }
      for (int r = by / kCornerBlock; r <= by / kCornerBlock + 1; ++r) {
        if (r < 1 || r >= field.blocks_across(height)) continue;
        int lo, hi;
        band_span(r, by, by + bh, height, lo, hi);
        for (int y = lo; y < hi; ++y)
          std::copy_n(probes + (y - by) * bw, bw, &field.in_row_band(r, bx, y));
      }
      const InteriorPixels along_x = interior_pixels(bx, width), along_y = interior_pixels(by, height);
      if (along_x.count() > 0 && along_y.count() > 0) {
        const size_t tl = field.index(field.rect.x0 + along_x.first, field.rect.y0 + along_y.first);
        flag_hidden_block(source, probes + (along_y.first - by) * bw + (along_x.first - bx), bw, field.corners(tl),
                          along_x.count(), along_y.count(), settings, field.hidden.get() + tl, field.footprint_at(tl),
                          width);
      }
    }
  }
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

// The field's bands, each flagged as one task once every block is traced: zero without the
// hidden-detail flags.
template <class Probe>
size_t field_border_tasks(const CornerField<Probe>& field) {
  if (!field.hidden) return 0;
  return size_t(field.blocks_across(field.rect.width) - 1 + field.blocks_across(field.rect.height) - 1);
}

// The flags of the pixels whose stencil straddles blocks, from band `task`: a column band
// flags the three columns of pixels at its boundary, a row band the three rows, less the
// pixels a column band flags.
template <SampleSource S>
void flag_field_border(const S& source, const AdaptiveSettings& settings, CornerFieldOf<S>& field, size_t task,
                       AaStats& stats) {
  if constexpr (HiddenDetailSource<S>) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point t0 = Clock::now();
    const int width = field.rect.width, height = field.rect.height;
    const int columns = field.blocks_across(width) - 1;
    // Pixels have a stencil in the field where their TL corner is at offsets 1 .. size - 3.
    const int last_x = width - 3, last_y = height - 3;
    HiddenFlag* hidden = field.hidden.get();
    if (task < size_t(columns)) {
      const int c = int(task) + 1, boundary = c * kCornerBlock;
      for (int x = std::max(1, boundary - 2); x <= std::min(boundary, last_x); ++x) {
        const size_t tl = size_t(width) + size_t(x);
        flag_hidden_block(source, &field.in_column_band(c, x, 1), 2 * kBandHalf, field.corners(tl), 1, last_y,
                          settings, hidden + tl, field.footprint_at(tl), width);
      }
    } else {
      const int r = int(task) - columns + 1, boundary = r * kCornerBlock;
      for (int y = std::max(1, boundary - 2); y <= std::min(boundary, last_y); ++y)
        for (int bx = 0; bx < width; bx += kCornerBlock) {
          // The pixels of this block of columns no column band flags.
          const InteriorPixels along_x = interior_pixels(bx, width);
          if (along_x.count() == 0) continue;
          const size_t tl = size_t(y) * size_t(width) + size_t(along_x.first);
          flag_hidden_block(source, &field.in_row_band(r, along_x.first, y), width, field.corners(tl),
                            along_x.count(), 1, settings, hidden + tl, field.footprint_at(tl), width);
        }
    }
    stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
  }
}

// What the field's corners beyond `region`'s own pixel corners cost (the curvature ring,
// the Mitchell margin), in AaStats::margin_rays.
inline uint64_t field_margin_corners(const CornerRect& rect, const TileRect& region) {
  return rect.count() - own_corners(region);
}

// A tile's corner grid (and its hidden-detail flags, computed when the field was traced)
// from the field, as trace_corners would have traced it; no rays, no source needed
// (call as gather_corners<S>).
template <SampleSource S>
void gather_corners(const CornerFieldOf<S>& field, const TileTarget& target, const AdaptiveSettings& settings,
                    CornerGrid& grid, AaStats& stats) {
  if (target.rect.width() <= 0 || target.rect.height() <= 0) return;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  const CornerLayout layout = corner_layout(target, settings);
  assert(field.rect.contains(layout.x0, layout.y0) &&
         field.rect.contains(layout.x0 + layout.width - 1, layout.y0 + layout.height - 1));
  const bool probing = flags_hidden<S>(settings);
  const bool footprint = corrects_footprint<S>(settings);
  grid.reserve(layout.corners(), probing ? layout.pixels() : 0, footprint ? layout.pixels() : 0);
  for (int j = 0; j < layout.height; ++j) {
    const size_t from = field.index(layout.x0, layout.y0 + j), to = size_t(j) * size_t(layout.width);
    std::copy_n(field.linear.get() + from, layout.width, grid.linear.begin() + to);
    std::copy_n(field.display.get() + from, layout.width, grid.display.begin() + to);
    std::copy_n(field.signature.get() + from, layout.width, grid.signature.begin() + to);
  }
  if (probing) {
    const TileRect region = layout.region;
    for (int y = region.y0; y < region.y1; ++y) {
      std::copy_n(field.hidden.get() + field.index(region.x0, y), region.width(),
                  grid.hidden.begin() + size_t(y - region.y0) * size_t(region.width()));
      if (footprint)
        std::copy_n(field.footprint.get() + field.index(region.x0, y), region.width(),
                    grid.footprint.begin() + size_t(y - region.y0) * size_t(region.width()));
    }
  }
  stats.seconds_corners += std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace zz
