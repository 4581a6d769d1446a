// Renders a frame: 64x64 tiles as oneTBB tasks, each tile sampled by the chosen
// sampler through a SceneSource. Output is bit-identical whatever the thread count or
// tile order: a pixel's value depends only on its own (deterministic) samples.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <future>

#include "aa/aa_stats.h"
#include "aa/adaptive_settings.h"
#include "aa/uniform.h"
#include "core/geo_map.h"
#include "core/tonemap.h"
#include "core/film.h"
#include "render/ray_counters.h"
#include "render/shader.h"

namespace zz {

enum class AaMode { None, Uniform, Adaptive };

struct RenderSettings {
  int width = 512;
  int height = 512;
  // Render only these pixels (half-open, frame coordinates; empty = the whole frame).
  // The film then holds just the region; its pixels are bit-identical to the same pixels
  // of a full-frame render (same tile grid from the frame origin, same margins).
  TileRect region;
  AaMode aa = AaMode::Adaptive;
  UniformSettings uniform;
  AdaptiveSettings adaptive;  // its tonemap is set from `tonemap` by render_frame
  ToneMap tonemap;
  int threads = 0;  // 0 = all cores
  int tile_size = kTileSize;
  bool centre_out = false;  // tile order (no effect on the image)
  // Adaptive: level 1 traced once for the whole region (aa/corner_field.h) when it fits in
  // memory, else per tile; the same image either way, fewer rays with the field.
  bool corner_field = true;
};

struct RenderStats {
  RayCounters rays;
  uint64_t samples = 0;  // image-plane points evaluated (uniform modes)
  uint64_t margin_samples = 0;  // of those, the lattice's corners beyond one per pixel (UniformStats::margin)
  AaStats aa;            // adaptive mode: rays by level, level fractions, zones
  double render_seconds = 0.0;
  int tiles = 0;
  bool cancelled = false;
};

struct RenderCallbacks {
  // Called from a worker thread as soon as a tile's pixels are final, with the rays the
  // tile traced (for progress and rays/s).
  std::function<void(const TileRect&, const RayCounters&)> tile_done;
  // Called from a worker thread after each block of level-1 corners traced for the whole
  // region before any tile (corner_field_plan(settings).blocks of them), with its rays.
  std::function<void(const RayCounters&)> corners_done;
  // Set by another thread to stop promptly; unfinished tiles are left as they were.
  const std::atomic<bool>* cancel = nullptr;
};

// Level 1 for the whole region at once (aa/corner_field.h): the memory it takes and the
// blocks it is traced in before the tiles; zeros when the renderer traces corners per
// tile instead (not adaptive, corner_field off, or above kCornerFieldBudget). `bytes` is
// an upper bound: a scene without textures leaves the footprint correction's part unused.
struct CornerFieldPlan {
  uint64_t bytes = 0;
  size_t blocks = 0;
};
CornerFieldPlan corner_field_plan(const RenderSettings& settings);

// The region a render covers: settings.region, or the whole frame if it is empty.
// Throws zz::Error if the region is not a non-empty rect inside the frame.
TileRect render_region(const RenderSettings& settings);

void render_frame(const Shader& shader, const Camera& camera, const GeoMap& geo, const RenderSettings& settings,
                  Film& film, RenderStats& stats, const RenderCallbacks& callbacks = {});

// The same frame with the visibility map still being made (e.g. by the Vulkan pass on
// another thread): level 1 of the whole region (aa/corner_field.h) is traced while it
// is pending, the map is awaited before the first classification (on the per-tile path,
// frames above the field's budget, it is awaited first). Bit-identical to
// the overload above; an exception from the map's producer is rethrown here.
void render_frame(const Shader& shader, const Camera& camera, const std::shared_future<GeoMap>& geo,
                  const RenderSettings& settings, Film& film, RenderStats& stats, const RenderCallbacks& callbacks = {});

}  // namespace zz
