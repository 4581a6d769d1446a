// The scene and image options `zigzag render` and `zigzag view` share: one set of flags,
// parsed once, turned into RenderSettings and VisibilitySettings in one place, so the
// viewer's screenshot and a render with the same arguments are the same image.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "gpu/visibility.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace zz {

struct RenderOptions {
  int width = 0, height = 0;  // 0 = the scene's
  std::string aa = "adaptive";
  // Defaults chosen by the accuracy/time report at 1024² (reports/REPORT.md, "Chosen
  // defaults"): the lowest worst-scene display error among settings within 1.75 rays/px.
  float eps = 0.05f;
  std::string tables = "tuned";  // beats paper on the held-out edge population (tools/table_tuner)
  std::string geo_policy = "all";
  std::string filter = "box";
  int spp = 25;
  std::string pattern = "stratified";
  std::string edges = "vulkan";
  int edge_ss = VisibilitySettings{}.supersample;
  float edge_angle = VisibilitySettings{}.normal_angle_deg;
  float edge_depth = VisibilitySettings{}.depth_rel;
  int vk_device = -1;
  bool vk_validate = false;
  int threads = 0;
  std::string assets;
  float exposure = 0.0f;  // 0 = the scene's
  int max_depth = -1;     // -1 = the scene's
};

// Registers the shared flags on a subcommand.
void add_render_options(CLI::App* cmd, RenderOptions& o);

// Frame settings for a loaded scene; throws zz::Error for inconsistent choices
// (e.g. --pattern lattice without --spp 25, a non-square --spp).
RenderSettings make_render_settings(const RenderOptions& o, const Scene& scene);

VisibilitySettings make_visibility_settings(const RenderOptions& o);

// The adaptive sampler with the visibility map on needs Vulkan; nothing else does.
bool wants_visibility_map(const RenderOptions& o);

}  // namespace zz
