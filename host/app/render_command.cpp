// `zigzag render SCENE... [options]`: headless batch rendering to PNG/EXR + JSON stats.
// Every option is checked before the first scene is loaded; after that, one failed job
// is reported and the others still run; the exit code says whether any failed.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "accel/bvh.h"
#include "app/batch_options.h"
#include "app/commands.h"
#include "app/output_paths.h"
#include "app/progress.h"
#include "app/render_stats_json.h"
#include "core/error.h"
#include "gpu/device.h"
#include "gpu/visibility.h"
#include "render/aov.h"
#include "render/image_io.h"
#include "render/memory_budget.h"
#include "render/renderer.h"
#include "scene/loader.h"

namespace zz {

namespace {

bool wants_geo_map(const BatchOptions& o) {
  if (wants_visibility_map(o.render)) return true;
  for (const auto& aov : o.aovs)
    if (aov.first == "geo" && o.render.edges == EdgeMode::Vulkan) return true;
  return false;
}

std::vector<int> select_cameras(const BatchOptions& o, const Scene& scene, const std::filesystem::path& scene_path) {
  std::vector<int> cameras;
  if (o.all_cameras()) {
    for (size_t i = 0; i < scene.cameras.size(); ++i) cameras.push_back(int(i));
    return cameras;
  }
  int index = -1;
  try {
    size_t used = 0;
    index = std::stoi(o.camera, &used);
    if (used != o.camera.size()) index = -1;
  } catch (const std::exception&) {
  }
  if (index < 0 || index >= int(scene.cameras.size()))
    throw Error(scene_path.string() + ": --camera " + o.camera + " does not exist (the scene has " +
                std::to_string(scene.cameras.size()) + " camera(s); use 0.." +
                std::to_string(scene.cameras.size() - 1) + " or all)");
  return {index};
}

// Everything besides the frame size and exposure that decides the image's pixels: the
// parts of one frame carry the same value, and `zigzag merge` refuses to mix others.
std::string image_settings(const BatchOptions& o, const Scene& scene) {
  const RenderOptions& r = o.render;
  nlohmann::json j = {{"aa", name_of(kAaModes, r.aa)}, {"max_depth", scene.max_depth}, {"time", scene.time}};
  if (r.aa == AaMode::Adaptive)
    j["adaptive"] = {{"eps", r.adaptive.eps},
                     {"tables", r.adaptive.tables->name},
                     {"geo_policy", name_of(kGeoPolicies, r.adaptive.geo_policy)},
                     {"filter", name_of(kFilters, r.adaptive.filter)},
                     {"edges", name_of(kEdgeModes, r.edges)}};
  if (wants_visibility_map(r)) j["edge"] = {{"ss", r.edge_ss}, {"angle", r.edge_angle}, {"depth", r.edge_depth}};
  if (r.aa == AaMode::Uniform) j["uniform"] = {{"spp", r.spp}, {"pattern", name_of(kUniformPatterns, r.pattern)}};
  return j.dump();
}

void write_stats(const std::filesystem::path& path, const nlohmann::json& j) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream f(path);
  f << j.dump(2) << "\n";
  if (!f) throw Error("cannot write " + path.string());
}

void render_job(const BatchOptions& o, const std::filesystem::path& scene_path, VulkanContext* vulkan) {
  LoadOptions load;
  load.assets_dir = o.render.assets;
  load.quiet = o.quiet;
  load.frame = o.frame;
  load.time = o.time;
  load.fps = o.fps;
  auto t = std::chrono::steady_clock::now();
  Scene scene = load_scene(scene_path, load);
  if (o.render.max_depth >= 0) scene.max_depth = o.render.max_depth;
  const double load_s = seconds_since(t);
  const std::string scene_name = scene_path.stem().string();
  const std::vector<int> cameras = select_cameras(o, scene, scene_path);

  t = std::chrono::steady_clock::now();
  BvhBuildStats bvh_stats;
  const Bvh bvh = Bvh::build(scene.positions, &bvh_stats);
  const double bvh_s = seconds_since(t);
  const Shader shader(scene, bvh);
  std::unique_ptr<VisibilityPass> visibility;
  if (vulkan) visibility = std::make_unique<VisibilityPass>(*vulkan, scene);

  for (int camera_index : cameras) {
    const auto t_job = std::chrono::steady_clock::now();
    RenderSettings settings = make_render_settings(o.render, scene);
    if (!o.region.empty()) settings.region = parse_region(o.region);
    const TileRect region = render_region(settings);
    const std::string what = o.region.empty() ? "a " + std::to_string(settings.width) + "x" +
                                                     std::to_string(settings.height) + " frame"
                                               : "a " + std::to_string(region.width()) + "x" +
                                                     std::to_string(region.height()) + " region";
    // A region's film is region-sized, but the visibility map still covers the frame.
    const uint64_t full_geo_map = visibility ? uint64_t(settings.width) * uint64_t(settings.height) : 0;
    check_memory(frame_bytes(region.width(), region.height(),
                             settings.threads > 0 ? settings.threads : int(std::thread::hardware_concurrency())) +
                     full_geo_map,
                 what.c_str());
    const int frame = scene.frame >= 0 ? scene.frame : int(std::lround(scene.time * scene.fps));
    const OutputKey key{scene_name, std::to_string(camera_index), frame};
    const std::filesystem::path output = expand_output_pattern(o.output_pattern(), key);

    GeoMap geo;
    VisibilityTimings edge_times;
    if (visibility)
      geo = visibility->run(scene.cameras[size_t(camera_index)], settings.width, settings.height,
                            make_visibility_settings(o.render), &edge_times);

    Film film;
    RenderStats stats;
    Progress progress(int(make_tiles(settings.width, settings.height, region, settings.tile_size).size()),
                      !o.quiet && isatty(STDERR_FILENO));
    RenderCallbacks callbacks;
    callbacks.tile_done = [&](const TileRect&, const RayCounters& rays) { progress.tile_done(rays.total()); };
    render_frame(shader, scene.cameras[size_t(camera_index)], geo, settings, film, stats, callbacks);

    t = std::chrono::steady_clock::now();
    write_film(output, film, settings.tonemap,
               {{"scene", scene_name}, {"camera", key.camera}, {"settings", image_settings(o, scene)}});
    const double write_s = seconds_since(t);
    const GeoMap region_geo = film.is_region() ? crop(geo, region) : GeoMap{};
    for (const auto& [name, file] : o.aovs)
      write_aov(name, expand_output_pattern(file, key, "--aov"), film, film.is_region() ? region_geo : geo);

    JobRecord record;
    record.scene_name = scene_name;
    record.camera = camera_index;
    record.output = output.string();
    record.options = &o.render;
    record.settings = &settings;
    record.stats = &stats;
    record.scene = &scene;
    record.shader = &shader;
    record.bvh = &bvh_stats;
    record.region = region;
    record.times = {load_s, bvh_s, write_s,
                    seconds_since(t_job) + (camera_index == cameras.front() ? load_s + bvh_s : 0.0)};
    if (visibility) {
      record.visibility = visibility.get();
      record.edge_times = &edge_times;
      record.geo = &geo;
      record.vulkan_device = vulkan->device_name();
    }
    const nlohmann::json j = render_stats_json(record);
    if (!o.stats.empty()) write_stats(expand_output_pattern(o.stats, key, "--stats"), j);
    if (!o.quiet) {
      std::string effects;
      for (const std::string& e : shader.effects().names()) effects += (effects.empty() ? "" : ",") + e;
      const double pixels = double(region.width()) * region.height();
      const std::string where = (film.is_region() ? " region " + o.region : std::string()) +
                                (scene.animated ? " frame " + std::to_string(frame) : std::string());
      std::fprintf(stderr,
                   "%s cam %d: %dx%d%s aa=%s %.2f rays/px (%.2f total) effects=[%s] render %.2fs (%.1f Mrays/s) "
                   "edges %.2fs load %.2fs bvh %.2fs -> %s\n",
                   scene_name.c_str(), camera_index, settings.width, settings.height, where.c_str(),
                   name_of(kAaModes, o.render.aa),
                   j["rays_per_pixel"].get<double>(), double(stats.rays.total()) / pixels, effects.c_str(),
                   stats.render_seconds, j["mrays_per_s"].get<double>(), visibility ? edge_times.total_s : 0.0,
                   load_s, bvh_s, output.string().c_str());
    }
  }
}

}  // namespace

void add_render_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BatchOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render scene files (.json rig, .gltf, .glb) to images");
  add_batch_options(cmd, *o);
  cmd->callback([o, &exit_code] {
    validate(*o);  // before anything is loaded: a bad invocation costs no render
    std::unique_ptr<VulkanContext> vulkan;
    if (wants_geo_map(*o)) {
      VulkanOptions vo;
      vo.device_index = o->render.vk_device;
      vo.validate = o->render.vk_validate;
      vulkan = VulkanContext::create(vo);  // throws with an install hint when there is no device
    }
    int failed = 0;
    for (const std::string& scene : o->scenes) {
      try {
        render_job(*o, scene, vulkan.get());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "zigzag: error: %s\n", e.what());
        ++failed;
      }
    }
    if (failed > 0 && o->scenes.size() > 1)
      std::fprintf(stderr, "zigzag: %d of %zu jobs failed\n", failed, o->scenes.size());
    exit_code = failed > 0 ? 1 : 0;
    if (vulkan && vulkan->validation_enabled() && vulkan->validation_message_count() > 0) {
      std::fprintf(stderr, "zigzag: %d Vulkan validation message(s)\n", vulkan->validation_message_count());
      exit_code = 1;
    }
  });
}

}  // namespace zz
