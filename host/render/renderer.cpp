#include "render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <memory>
#include <vector>

#include "aa/adaptive_sampler.h"
#include "aa/corner_field.h"
#include "core/error.h"
#include "core/fp_mode.h"
#include "core/worker_arena.h"
#include "render/scene_source.h"

namespace zz {

namespace {

struct TileResult {
  RayCounters rays;
  uint64_t samples = 0, margin_samples = 0;
  AaStats aa;
  bool done = false;
};

}  // namespace

TileRect render_region(const RenderSettings& settings) {
  const TileRect frame{0, 0, settings.width, settings.height};
  const TileRect& r = settings.region;
  if (r == TileRect{}) return frame;
  if (r.empty() || intersect(r, frame) != r)  // a --region the frame cannot hold, however often it runs
    throw UsageError("region " + std::to_string(r.x0) + "," + std::to_string(r.y0) + "," + std::to_string(r.x1) + "," +
                std::to_string(r.y1) + " must be a non-empty X0,Y0,X1,Y1 (half-open) inside the " +
                std::to_string(settings.width) + "x" + std::to_string(settings.height) + " frame");
  return r;
}

namespace {

void check_geo_size(const GeoMap& geo, const RenderSettings& settings) {
  if (!geo.empty() && (geo.width != settings.width || geo.height != settings.height))
    throw Error("visibility map is " + std::to_string(geo.width) + "x" + std::to_string(geo.height) +
                " but the frame is " + std::to_string(settings.width) + "x" + std::to_string(settings.height));
}

// The field level 1 of the render's region takes (aa/corner_field.h); none for the
// per-tile path.
CornerFieldShape field_shape(const RenderSettings& settings) {
  if (settings.aa != AaMode::Adaptive || !settings.corner_field) return {};
  return corner_field_shape<SceneSource>(render_region(settings), settings.width, settings.height, settings.adaptive);
}

// `geo` is the map when `pending` is null; else the map is `pending->get()`, awaited
// after level 1.
void render(const Shader& shader, const Camera& camera, const GeoMap* ready, const std::shared_future<GeoMap>* pending,
            const RenderSettings& settings, Film& film, RenderStats& stats, const RenderCallbacks& callbacks) {
  const auto start = std::chrono::steady_clock::now();
  if (ready) check_geo_size(*ready, settings);
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
  // Both follow textures: a scene without any has no texture detail to flag and no
  // footprint to correct (room 1024²: 9 % of the render spent finding that per pixel).
  // The corner field's shape stays the one corner_field_plan gave for the settings.
  if (!shader.effects().textures) adaptive.footprint = adaptive.textures = false;

  WorkerArena arena(settings.threads);
  auto for_tiles = [&](size_t count, auto&& body) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) body(i);
      });
    });
  };
  auto cancelled = [&] { return callbacks.cancel && callbacks.cancel->load(std::memory_order_relaxed); };
  // Made inside the arena: its tables of normal-map spread are built in parallel, and
  // --threads holds for them too (a farm worker's share of the cores).
  HiddenDetail detail;
  if (settings.aa == AaMode::Adaptive) arena.execute([&] { detail = HiddenDetail(shader.scene(), adaptive); });

  // Level 1 of the whole region first: it needs no map, so a pending map is made alongside.
  // Corners are pure functions of their positions, so the image is that of the per-tile path.
  const CornerFieldShape shape = field_shape(settings);
  const std::unique_ptr<CornerFieldOf<SceneSource>> field =
      shape.fits() ? std::make_unique<CornerFieldOf<SceneSource>>(shape.rect, flags_hidden<SceneSource>(adaptive),
                                                                   corrects_footprint<SceneSource>(adaptive))
                   : nullptr;
  RayCounters field_rays;
  AaStats field_stats;
  if (field) {
    const std::vector<CornerRect> blocks = corner_blocks(field->rect);
    std::vector<TileResult> traced(blocks.size());
    for_tiles(blocks.size(), [&](size_t index) {
      if (cancelled()) return;
      const ScopedFlushDenormals flush_denormals;
      SceneSource source(shader, rays, adaptive.signature, &detail, adaptive.tonemap);
      trace_field_block(source, adaptive, blocks[index], *field, traced[index].aa);
      traced[index].rays = source.counters;
      if (callbacks.corners_done) callbacks.corners_done(source.counters);
    });
    // The flags of the pixels whose probe stencil straddles blocks, from the blocks' bands.
    std::vector<AaStats> borders(field_border_tasks(*field));
    for_tiles(borders.size(), [&](size_t index) {
      if (cancelled()) return;
      const ScopedFlushDenormals flush_denormals;
      const SceneSource source(shader, rays, adaptive.signature, &detail, adaptive.tonemap);
      flag_field_border(source, adaptive, *field, index, borders[index]);
    });
    for (const TileResult& t : traced) field_rays += t.rays, field_stats.merge(t.aa);
    for (const AaStats& s : borders) field_stats.merge(s);
    field_stats.margin_rays += field_margin_corners(field->rect, region);
  }
  const GeoMap& geo = ready ? *ready : pending->get();
  if (!ready) check_geo_size(geo, settings);

  auto render_tile = [&](size_t index) {
    if (cancelled()) return;
    const ScopedFlushDenormals flush_denormals;  // MXCSR is per thread: set it in every task
    const TileTarget target = film.target(tiles[index]);
    SceneSource source(shader, rays, settings.aa == AaMode::Adaptive ? adaptive.signature : kSignatureNone, &detail,
                       adaptive.tonemap);
    TileResult& result = results[index];
    if (field) {
      CornerGrid& grid = AdaptiveScratch::local().corners;
      gather_corners<SceneSource>(*field, target, adaptive, grid, result.aa);
      refine_tile(source, target, geo, adaptive, grid, result.aa);
    } else if (settings.aa == AaMode::Adaptive) {
      render_tile_adaptive(source, target, geo, adaptive, result.aa);
    } else {
      UniformStats uniform_stats;
      const bool finished = render_tile_uniform(source, target, uniform, scratch.local().data(), uniform_stats,
                                                callbacks.cancel);
      result.samples = uniform_stats.samples;
      result.margin_samples = uniform_stats.margin;
      if (!finished) return;  // not done: the frame reports itself cancelled
    }
    result.rays += source.counters;
    result.done = true;
    if (callbacks.tile_done) callbacks.tile_done(tiles[index], result.rays);
  };

  for_tiles(tiles.size(), render_tile);

  stats = {};
  stats.rays = field_rays;
  stats.aa = field_stats;
  for (const TileResult& r : results) {
    stats.rays += r.rays;
    stats.samples += r.samples;
    stats.margin_samples += r.margin_samples;
    stats.aa.merge(r.aa);
    if (!r.done) stats.cancelled = true;
  }
  stats.tiles = int(tiles.size());
  stats.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

CornerFieldPlan corner_field_plan(const RenderSettings& settings) {
  const CornerFieldShape shape = field_shape(settings);
  if (!shape.fits()) return {};
  return {shape.bytes, corner_blocks(shape.rect).size()};
}

void render_frame(const Shader& shader, const Camera& camera, const GeoMap& geo, const RenderSettings& settings,
                  Film& film, RenderStats& stats, const RenderCallbacks& callbacks) {
  render(shader, camera, &geo, nullptr, settings, film, stats, callbacks);
}

void render_frame(const Shader& shader, const Camera& camera, const std::shared_future<GeoMap>& geo,
                  const RenderSettings& settings, Film& film, RenderStats& stats, const RenderCallbacks& callbacks) {
  render(shader, camera, nullptr, &geo, settings, film, stats, callbacks);
}

}  // namespace zz
