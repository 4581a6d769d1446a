// The `--stats FILE.json` record of one render job: rays by type and per pixel, the AA
// levels, BVH statistics, effects, and the time of each stage.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "accel/bvh.h"
#include "app/render_options.h"
#include "core/geo_map.h"
#include "gpu/visibility.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace zz {

struct StageTimes {
  double load = 0, bvh = 0, write = 0, total = 0;
  double frame = 0;  // visibility map + render, wall (they overlap unless --edges-serial)
};

// The visibility map's one-off set-up and its thread's time in one frame (render_command.cpp):
// device_wait, before the frame (a scene's first), the wait for the Vulkan device that the
// load and BVH did not hide; on the map's thread, inside the frame, the scene's upload (a
// scene's first frame) and prepare (the targets and flag pipeline: a new frame size), then
// VisibilityPass::run; total: the map thread's wall, upload and prepare included.
struct MapSetup {
  double device_wait_s = 0, upload_s = 0, prepare_s = 0, total_s = 0;
};

// Everything one job reports; the visibility fields are used when `edge_times` is set.
struct JobRecord {
  std::string scene_name;
  int camera = 0;
  std::string output;
  const RenderOptions* options = nullptr;
  const RenderSettings* settings = nullptr;
  const RenderStats* stats = nullptr;
  const Scene* scene = nullptr;
  std::optional<int> frame;  // the frame {frame} names; none for a --time between frames
  const Shader* shader = nullptr;
  const BvhBuildStats* bvh = nullptr;
  StageTimes times;
  uint64_t memory_estimate_bytes = 0;  // peak resident memory expected for the job
  const VisibilityTimings* edge_times = nullptr;
  MapSetup map_setup;
  const GeoMap* geo = nullptr;
  std::string vulkan_device;
  TileRect region;  // the pixels rendered (the whole frame unless --region)
  // The AOV channels written into the EXR, and the centre rays traced for depth, normal
  // and albedo (render/primary_hits.h: not part of `stats`, which counts the image's rays).
  std::vector<std::string> aov_channels;
  RayCounters aov_rays;
  double aov_seconds = 0;
};

// The adaptive options, as the stats record and the image's settings stamp (what
// `zigzag merge` compares) both give them.
nlohmann::json adaptive_settings_json(const AdaptiveOptions& a);

nlohmann::json render_stats_json(const JobRecord& r);

}  // namespace zz
