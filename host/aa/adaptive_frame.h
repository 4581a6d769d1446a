// A whole frame through the adaptive sampler: level 1 for the frame at once (corner_field.h,
// per tile above its budget or with corner_field = false), then tiles as TBB tasks,
// per-tile stats merged in order. Used by the analytic harness, the tuner and the tests;
// the renderer schedules the same steps itself (render/renderer.cpp).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <vector>

#include "aa/adaptive_sampler.h"
#include "aa/corner_field.h"
#include "core/film.h"
#include "core/worker_arena.h"

namespace zz {

// Each block and tile gets its own copy of `source` (so per-task state such as ray
// counters never races). threads = 0: TBB's default.
template <SampleSource S>
AaStats render_frame_adaptive(const S& source, Film& frame, const GeoMap& geo, const AdaptiveSettings& settings,
                              int tile_size = kTileSize, int threads = 0, bool corner_field = true) {
  const std::vector<TileRect> tiles = make_tiles(frame.width, frame.height, tile_size);
  const TileRect whole{0, 0, frame.width, frame.height};
  const auto field = corner_field ? make_corner_field<S>(whole, frame.width, frame.height, settings) : nullptr;
  const std::vector<CornerRect> blocks = field ? corner_blocks(field->rect) : std::vector<CornerRect>();
  std::vector<AaStats> block_stats(blocks.size()), tile_stats(tiles.size());
  WorkerArena arena(threads);
  auto for_each = [&](size_t count, auto&& body) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) body(i);
      });
    });
  };
  for_each(blocks.size(), [&](size_t b) {
    S local = source;
    trace_field_block(local, settings, blocks[b], *field, block_stats[b]);
  });
  const size_t borders = field ? field_border_tasks(*field) : 0;
  std::vector<AaStats> border_stats(borders);
  for_each(borders, [&](size_t b) { flag_field_border(source, settings, *field, b, border_stats[b]); });
  for_each(tiles.size(), [&](size_t t) {
    const TileTarget target = frame.target(tiles[t]);
    S local = source;
    if (field) {
      CornerGrid& grid = AdaptiveScratch::local().corners;
      gather_corners<S>(*field, target, settings, grid, tile_stats[t]);
      refine_tile(local, target, geo, settings, grid, tile_stats[t]);
    } else {
      render_tile_adaptive(local, target, geo, settings, tile_stats[t]);
    }
  });
  AaStats total;
  for (const AaStats& s : block_stats) total.merge(s);
  for (const AaStats& s : border_stats) total.merge(s);
  if (field) total.margin_rays += field_margin_corners(field->rect, whole);
  for (const AaStats& s : tile_stats) total.merge(s);
  return total;
}

}  // namespace zz
