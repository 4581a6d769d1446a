// The `--stats FILE.json` record of one render job: rays by type and per pixel, the AA
// levels, BVH statistics, effects, and the time of each stage.
#pragma once

#include <nlohmann/json.hpp>

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

// Everything one job reports; the visibility fields are used when `visibility` is set.
struct JobRecord {
  std::string scene_name;
  int camera = 0;
  std::string output;
  const RenderOptions* options = nullptr;
  const RenderSettings* settings = nullptr;
  const RenderStats* stats = nullptr;
  const Scene* scene = nullptr;
  const Shader* shader = nullptr;
  const BvhBuildStats* bvh = nullptr;
  StageTimes times;
  uint64_t memory_estimate_bytes = 0;  // peak resident memory expected for the job
  const VisibilityPass* visibility = nullptr;
  const VisibilityTimings* edge_times = nullptr;
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
