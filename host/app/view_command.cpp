// `zigzag view SCENE [options]`: the interactive viewer (host/viewer). Takes the same
// scene and image options as `zigzag render`, so a `view --exit-after-frame --screenshot`
// and a `render` with the same arguments give the same PNG bytes.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "accel/bvh.h"
#include "app/option_checks.h"
#include "app/output_paths.h"
#include "app/render_options.h"
#include "core/error.h"
#include "core/file_io.h"
#include "scene/camera_select.h"
#include "gpu/visibility.h"
#include "render/image_io.h"
#include "render/memory_budget.h"
#include "render/renderer.h"
#include "scene/loader.h"
#include "viewer/script.h"
#include "viewer/viewer.h"

namespace zz {

namespace {

struct ViewOptions {
  std::string scene;
  std::string camera = "0";  // an index or a name
  RenderOptions render;
  int preview_scale = 4;
  std::string screenshot_dir = ".";
  bool exit_after_frame = false;
  std::string screenshot;
  std::string script;
  double script_timeout = 600;
};

// A screenshot is the 8-bit display image, as the window shows it: checked before anything
// loads, as render checks -o (a float format would hold display values, not radiance).
void check_screenshot(const std::string& option, const std::string& path, const std::vector<std::string>& inputs) {
  preflight_output(option, path, true,
                   " (a screenshot is the 8-bit display image: use .png; .jpg, .tif, .bmp, .tga, .webp also work)");
  check_not_an_input(option, path, inputs, "a file of the scene,");
  if (writes_radiance(path))
    throw Error(option + " " + path + ": a screenshot is the 8-bit display image (.png, .jpg, .tif, ...); for "
                "linear radiance use `zigzag render -o FILE" + lowercase_extension(path) + "`");
}

int view(const ViewOptions& o) {
  const auto started = std::chrono::steady_clock::now();
  as_usage_checks([&] {
    validate(o.render);
    std::optional<std::vector<std::string>> inputs;  // the scene's files, read once a screenshot asks
    auto check = [&](const std::string& option, const std::string& path) {
      if (!inputs) inputs = scene_files(o.scene, load_options(o.render, true));
      check_screenshot(option, path, *inputs);
    };
    if (!o.screenshot.empty()) check("--screenshot", o.screenshot);
    for (const ScriptEvent& e : parse_script(o.script))
      if (e.kind == ScriptEvent::Kind::Screenshot) check("--script screenshot:", e.text);
  });
  // Fail fast, before loading anything, when no window can be opened.
  require_display();
  const auto t0 = std::chrono::steady_clock::now();
  Scene scene = load_scene(o.scene, load_options(o.render, false));
  if (o.render.max_depth >= 0) scene.max_depth = o.render.max_depth;
  warn_outside_animation(scene, false);
  size_t camera = 0;
  try {
    camera = find_camera(scene, o.camera);
  } catch (const Error& e) {
    throw Error(o.scene + ": --camera " + o.camera + ": " + e.what() +
                (o.camera == "all" ? " (the viewer shows one camera: an index or a name; 'all' is render's)" : ""));
  }
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  ViewerOptions v;
  v.name = std::filesystem::path(o.scene).stem().string();
  v.started = started;
  v.camera = scene.cameras[camera];
  if (!scene.positions.empty()) {
    const auto [lo, hi] = scene.bounds();
    v.scene_centre = 0.5f * (lo + hi);
    v.scene_radius = 0.5f * glm::length(hi - lo);
  }
  v.settings = make_render_settings(o.render, scene, scene.cameras[camera]);
  // The first frame's memory, as render checks it (the window may grow later; its size
  // is bounded by kMaxImageSide).
  check_memory(render_bytes(v.settings, TileRect{0, 0, v.settings.width, v.settings.height}, scene) +
                   uint64_t(v.settings.width) * uint64_t(v.settings.height) * 16,  // display and preview images
               ("a " + std::to_string(v.settings.width) + "x" + std::to_string(v.settings.height) + " frame").c_str());
  v.tweaks.adaptive = o.render.aa == AaMode::Adaptive;
  v.tweaks.eps = v.settings.adaptive.eps;
  v.tweaks.mitchell = v.settings.adaptive.filter == Filter::Mitchell;
  v.tweaks.edges = o.render.edges == EdgeMode::Vulkan;
  RenderOptions with_map = o.render;  // the crease as `render --edges vulkan` would take it
  with_map.edges = EdgeMode::Vulkan;
  v.tweaks.map_crease = map_crease(with_map);
  v.preview_scale = o.preview_scale;
  v.validate = o.render.vk_validate;
  v.vk_device = o.render.vk_device;
  if (o.render.aa == AaMode::Adaptive) {
    // The same visibility map as `zigzag render` (same settings, same device), built on
    // the viewer's Vulkan context (shared with presentation; the context serialises the queue).
    const VisibilitySettings vs = make_visibility_settings(o.render);
    // The pass (the scene's upload, the pipelines) is made on the render thread when a map
    // is first wanted: with --edges off perhaps never (E turns the map on), and not on the
    // UI thread before the window shows anything.
    v.make_geo_source = [&scene, vs](VulkanContext& context) -> ProgressiveRenderer::GeoSource {
      auto pass = std::make_shared<std::unique_ptr<VisibilityPass>>();
      return [pass, vs, &scene, &context](const Camera& camera, int width, int height, const std::atomic<bool>* cancel) {
        if (!*pass) *pass = std::make_unique<VisibilityPass>(context, scene);
        return (*pass)->run(camera, width, height, vs, nullptr, std::nullopt, cancel);
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
  cmd->add_option("--camera", o->camera, "Camera index or name");
  add_render_options(cmd, o->render);
  cmd->add_option("--preview-scale", o->preview_scale, "Coarse preview at 1/N size before each frame, smaller while previews take over 1/30 s (1 = off)")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_option("--screenshot-dir", o->screenshot_dir, "Where the S key saves screenshots")->capture_default_str();
  CLI::Option* exit_after =
      cmd->add_flag("--exit-after-frame", o->exit_after_frame, "Quit after the first full frame (after --script)");
  cmd->add_option("--screenshot", o->screenshot, "With --exit-after-frame: save the final view to this PNG")
      ->needs(exit_after);
  cmd->add_option("--script", o->script,
                  "Scripted input, e.g. \"drag:100,100,200,120;wait;screenshot:a.png;quit\" "
                  "(drag/scroll/key/resize/wait/sleep/screenshot/quit)");
  cmd->add_option("--script-timeout", o->script_timeout,
                  "Seconds a scripted 'wait', 'screenshot' or 'key:S' may wait for the image before failing")
      ->capture_default_str()
      ->check(number_in(1e-3, 1e6));
  cmd->callback([o, &exit_code] { exit_code = view(*o); });
}

}  // namespace zz
