// A whole frame through the adaptive sampler: tiles as TBB tasks, per-tile stats merged
// in tile order. Used by the analytic harness, the tuner and the tests; the renderer has
// its own scheduler but calls the same render_tile_adaptive.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <vector>

#include "aa/adaptive_sampler.h"
#include "core/film.h"

namespace zz {

// Each tile gets its own copy of `source` (so per-tile state such as ray counters never
// races). threads = 0: TBB's default.
template <SampleSource S>
AaStats render_frame_adaptive(const S& source, Film& frame, const GeoMap& geo,
                              const AdaptiveSettings& settings, int tile_size = kTileSize, int threads = 0) {
  const std::vector<TileRect> tiles = make_tiles(frame.width, frame.height, tile_size);
  std::vector<AaStats> tile_stats(tiles.size());
  auto body = [&](const tbb::blocked_range<size_t>& r) {
    for (size_t t = r.begin(); t != r.end(); ++t) {
      const TileTarget target = frame.target(tiles[t]);
      S local = source;
      render_tile_adaptive(local, target, geo, settings, tile_stats[t]);
    }
  };
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] { tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), body); });
  AaStats total;
  for (const AaStats& s : tile_stats) total.merge(s);
  return total;
}

}  // namespace zz
