// `zigzag view SCENE [options]`: the interactive viewer (host/viewer). Takes the same
// scene and image options as `zigzag render`, so a `view --exit-after-frame --screenshot`
// and a `render` with the same arguments give the same PNG bytes.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include "accel/bvh.h"
#include "core/error.h"
#include "gpu/visibility.h"
#include "render/renderer.h"
#include "scene/loader.h"
#include "viewer/viewer.h"

namespace zz {

namespace {

struct ViewOptions {
  std::string scene;
  int camera = 0;
  int width = 0, height = 0;
  std::string aa = "adaptive";
  float eps = 0.1f;
  std::string tables = "paper";
  std::string geo_policy = "paper";
  std::string filter = "box";
  std::string edges = "vulkan";
  int edge_ss = 4;
  float edge_angle = VisibilitySettings{}.normal_angle_deg;
  float edge_depth = VisibilitySettings{}.depth_rel;
  int spp = 25;
  std::string pattern = "stratified";
  int threads = 0;
  std::string assets;
  float exposure = 0.0f;  // 0 = the scene's
  int max_depth = -1;     // -1 = the scene's
  int preview_scale = 4;
  int vk_device = -1;
  bool validate = false;
  std::string screenshot_dir = ".";
  bool exit_after_frame = false;
  std::string screenshot;
  std::string script;
  double script_timeout = 600;
};

RenderSettings make_view_settings(const ViewOptions& o, const Scene& scene) {
  RenderSettings s;
  s.width = o.width > 0 ? o.width : scene.default_width;
  s.height = o.height > 0 ? o.height : scene.default_height;
  s.threads = o.threads;
  s.tonemap.exposure = o.exposure > 0.0f ? o.exposure : scene.exposure;
  if (o.aa == "adaptive") {
    s.aa = AaMode::Adaptive;
    s.adaptive.eps = o.eps;
    s.adaptive.tables = &parse_table_set(o.tables);
    s.adaptive.geo_policy = parse_geo_policy(o.geo_policy);
    s.adaptive.filter = parse_filter(o.filter);
  } else if (o.aa == "none") {
    s.aa = AaMode::None;
  } else if (o.aa == "uniform") {
    s.aa = AaMode::Uniform;
    if (o.pattern == "lattice") {
      if (o.spp != 25) throw Error("--pattern lattice needs --spp 25 (the 25-point lattice)");
      s.uniform = {UniformPattern::Lattice, 25};
    } else {
      const int n = int(std::lround(std::sqrt(double(o.spp))));
      if (o.spp < 1 || n * n != o.spp)
        throw Error("--spp must be a perfect square (4, 9, 16, 25, ...) for --pattern " + o.pattern);
      s.uniform = {o.pattern == "grid" ? UniformPattern::Grid : UniformPattern::Stratified, o.spp};
    }
  }
  return s;
}

int view(const ViewOptions& o) {
  const auto started = std::chrono::steady_clock::now();
  // Fail fast, before loading anything, when no window can be opened.
  require_display();
  const auto t0 = std::chrono::steady_clock::now();
  LoadOptions load;
  load.assets_dir = o.assets;
  Scene scene = load_scene(o.scene, load);
  if (o.max_depth >= 0) scene.max_depth = o.max_depth;
  if (o.camera < 0 || o.camera >= int(scene.cameras.size()))
    throw Error(o.scene + ": --camera " + std::to_string(o.camera) + " does not exist (the scene has " +
                std::to_string(scene.cameras.size()) + " camera(s))");
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  ViewerOptions v;
  v.name = std::filesystem::path(o.scene).stem().string();
  v.started = started;
  v.camera = scene.cameras[size_t(o.camera)];
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec3& p : scene.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  if (!scene.positions.empty()) {
    v.scene_centre = 0.5f * (lo + hi);
    v.scene_radius = 0.5f * glm::length(hi - lo);
  }
  v.settings = make_view_settings(o, scene);
  v.tweaks.eps = v.settings.adaptive.eps;
  v.tweaks.mitchell = v.settings.adaptive.filter == Filter::Mitchell;
  v.tweaks.edges = o.edges == "vulkan";
  v.preview_scale = o.preview_scale;
  v.validate = o.validate;
  v.vk_device = o.vk_device;
  if (o.aa == "adaptive") {
    // The same visibility map as `zigzag render` (same settings, same device), built on
    // the viewer's Vulkan context; its queue is shared with presentation, hence the lock.
    VisibilitySettings vs;
    vs.supersample = o.edge_ss;
    vs.normal_angle_deg = o.edge_angle;
    vs.depth_rel = o.edge_depth;
    v.make_geo_source = [&scene, vs](VulkanContext& context, std::mutex& queue) -> ProgressiveRenderer::GeoSource {
      std::shared_ptr<VisibilityPass> pass;
      {
        std::lock_guard<std::mutex> lock(queue);
        pass = std::make_shared<VisibilityPass>(context, scene);
      }
      return [pass, vs, &queue](const Camera& camera, int width, int height) {
        std::lock_guard<std::mutex> lock(queue);
        return pass->run(camera, width, height, vs);
      };
    };
  }
  v.screenshot_dir = o.screenshot_dir;
  v.exit_after_frame = o.exit_after_frame;
  v.screenshot = o.screenshot;
  v.script = o.script;
  v.script_timeout_seconds = o.script_timeout;
  std::fprintf(stderr, "zigzag view: %s, %zu triangles, load + BVH %.2f s\n", v.name.c_str(), scene.triangle_count(),
               setup_s);
  return run_viewer(shader, v);
}

}  // namespace

void add_view_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view", "Open a scene in an interactive window (progressive tiles)");
  cmd->add_option("scene", o->scene, "Scene file (.json rig, .gltf, .glb)")->required();
  cmd->add_option("--camera", o->camera, "Camera index")->check(CLI::NonNegativeNumber);
  cmd->add_option("--width", o->width, "Window/image width (default: the scene's)")->check(CLI::Range(1, 16384));
  cmd->add_option("--height", o->height, "Window/image height (default: the scene's)")->check(CLI::Range(1, 16384));
  cmd->add_option("--aa", o->aa, "Antialiasing: adaptive | none | uniform")
      ->check(CLI::IsMember({"adaptive", "none", "uniform"}));
  cmd->add_option("--eps", o->eps, "Adaptive: colour threshold on display values (keys [ and ] change it)")
      ->check(CLI::Range(0.0f, 1.0f));
  cmd->add_option("--tables", o->tables, "Adaptive: zone table set (paper, tuned, all)");
  cmd->add_option("--geo-policy", o->geo_policy, "Adaptive: geo pixels trace per tables (paper) or every zone (all)");
  cmd->add_option("--filter", o->filter, "Adaptive: reconstruction filter box | mitchell (key F toggles)");
  cmd->add_option("--edges", o->edges, "Visibility map of geometric edges: vulkan | off (key E toggles)")
      ->check(CLI::IsMember({"vulkan", "off"}));
  cmd->add_option("--edge-ss", o->edge_ss, "Visibility map supersampling per axis")->check(CLI::Range(1, 16));
  cmd->add_option("--edge-angle", o->edge_angle, "Visibility map: normal angle threshold, degrees")
      ->check(CLI::Range(0.0f, 180.0f));
  cmd->add_option("--edge-depth", o->edge_depth, "Visibility map: relative distance threshold")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--spp", o->spp, "Samples per pixel for --aa uniform")->check(CLI::Range(1, 4096));
  cmd->add_option("--pattern", o->pattern, "Uniform pattern: grid | stratified | lattice")
      ->check(CLI::IsMember({"grid", "stratified", "lattice"}));
  cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  cmd->add_option("--assets", o->assets, "Directory of third-party models");
  cmd->add_option("--exposure", o->exposure, "Tone-mapping exposure (default: the scene's)")->check(CLI::PositiveNumber);
  cmd->add_option("--max-depth", o->max_depth, "Reflection/refraction bounces (default: the scene's)")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--preview-scale", o->preview_scale, "Coarse preview at 1/N size before each frame (1 = off)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--vk-device", o->vk_device, "Vulkan device index (default: first GPU, else lavapipe)");
  cmd->add_flag("--vk-validate", o->validate, "Vulkan validation layers; exit non-zero if they report anything");
  cmd->add_option("--screenshot-dir", o->screenshot_dir, "Where the S key saves screenshots");
  cmd->add_flag("--exit-after-frame", o->exit_after_frame, "Quit after the first full frame (after --script)");
  cmd->add_option("--screenshot", o->screenshot, "With --exit-after-frame: save the final view to this PNG");
  cmd->add_option("--script", o->script,
                  "Scripted input, e.g. \"drag:100,100,200,120;wait;screenshot:a.png;quit\" "
                  "(drag/scroll/key/resize/wait/screenshot/quit)");
  cmd->add_option("--script-timeout", o->script_timeout, "Seconds a scripted 'wait' may take before failing")
      ->check(CLI::PositiveNumber);
  cmd->callback([o, &exit_code] { exit_code = view(*o); });
}

}  // namespace zz
