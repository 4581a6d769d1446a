#include "render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <vector>

#include "aa/adaptive_sampler.h"
#include "core/error.h"
#include "core/fp_mode.h"
#include "render/scene_source.h"

namespace zz {

namespace {

struct TileResult {
  RayCounters rays;
  uint64_t samples = 0;
  AaStats aa;
  bool done = false;
};

}  // namespace

TileRect render_region(const RenderSettings& settings) {
  const TileRect frame{0, 0, settings.width, settings.height};
  const TileRect& r = settings.region;
  if (r == TileRect{}) return frame;
  if (r.empty() || intersect(r, frame) != r)
    throw Error("region " + std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," +
                std::to_string(r.y1) + " must be a non-empty X0,Y0,X1,Y1 (half-open) inside the " +
                std::to_string(settings.width) + "x" + std::to_string(settings.height) + " frame");
  return r;
}

void render_frame(const Shader& shader, const Camera& camera, const GeoMap& geo, const RenderSettings& settings,
                  Film& film, RenderStats& stats, const RenderCallbacks& callbacks) {
  const auto start = std::chrono::steady_clock::now();
  if (!geo.empty() && (geo.width != settings.width || geo.height != settings.height))
    throw Error("visibility map is " + std::to_string(geo.width) + "x" + std::to_string(geo.height) +
                " but the frame is " + std::to_string(settings.width) + "x" + std::to_string(settings.height));
  const TileRect region = render_region(settings);
  if (film.window() != region || film.frame_width != settings.width || film.frame_height != settings.height)
    film = Film(settings.width, settings.height, region);
  const CameraRays rays(camera, settings.width, settings.height);
  std::vector<TileRect> tiles = make_tiles(settings.width, settings.height, region, settings.tile_size);
  if (settings.centre_out) tiles = centre_out(std::move(tiles), settings.width, settings.height);
  std::vector<TileResult> results(tiles.size());

  const size_t scratch_size = size_t(settings.tile_size + 1) * (settings.tile_size + 1) +
                              size_t(settings.tile_size) * settings.tile_size;
  tbb::enumerable_thread_specific<std::vector<glm::vec3>> scratch([&] { return std::vector<glm::vec3>(scratch_size); });
  UniformSettings uniform = settings.uniform;
  if (settings.aa == AaMode::None) uniform = {UniformPattern::Center, 1};
  AdaptiveSettings adaptive = settings.adaptive;
  adaptive.tonemap = settings.tonemap;  // colours are compared as they will be displayed

  auto render_tile = [&](size_t index) {
    if (callbacks.cancel && callbacks.cancel->load(std::memory_order_relaxed)) return;
    const ScopedFlushDenormals flush_denormals;  // MXCSR is per thread: set it in every task
    const TileTarget target = film.target(tiles[index]);
    SceneSource source(shader, rays);
    TileResult& result = results[index];
    if (settings.aa == AaMode::Adaptive) {
      render_tile_adaptive(source, target, geo, adaptive, result.aa);
    } else {
      UniformStats uniform_stats;
      render_tile_uniform(source, target, uniform, scratch.local().data(), uniform_stats);
      result.samples = uniform_stats.samples;
    }
    result.rays = source.counters;
    result.done = true;
    if (callbacks.tile_done) callbacks.tile_done(tiles[index], result.rays);
  };

  const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) render_tile(i);
    });
  });

  stats = {};
  for (const TileResult& r : results) {
    stats.rays += r.rays;
    stats.samples += r.samples;
    stats.aa.merge(r.aa);
    if (!r.done) stats.cancelled = true;
  }
  stats.tiles = int(tiles.size());
  stats.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace zz
