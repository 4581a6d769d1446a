// `zigzag render SCENE... [options]`: headless batch rendering to PNG/EXR + JSON stats.
// One failed job is reported and the others still run; the exit code says whether any
// failed.
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "accel/bvh.h"
#include "app/commands.h"
#include "app/render_options.h"
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

struct BatchOptions {
  std::vector<std::string> scenes;
  std::string output;
  std::string stats;
  std::string camera = "0";
  std::vector<std::pair<std::string, std::string>> aovs;
  std::string region;  // X0,Y0,X1,Y1 or empty
  bool quiet = false;
  RenderOptions render;
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size()) s.replace(pos, from.size(), to);
  return s;
}

std::string expand_pattern(const std::string& pattern, const std::string& scene, const std::string& camera) {
  return replace_all(replace_all(pattern, "{scene}", scene), "{camera}", camera);
}

// "X0,Y0,X1,Y1" -> rect (checked against the frame later, by render_region).
TileRect parse_region(const std::string& text) {
  TileRect r;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d,%d,%d,%d%c", &r.x0, &r.y0, &r.x1, &r.y1, &tail) != 4)
    throw Error("--region " + text + ": expected X0,Y0,X1,Y1 (integer pixel bounds, half-open)");
  if (r.empty()) throw Error("--region " + text + ": the region is empty (need X0 < X1 and Y0 < Y1)");
  return r;
}

// Everything besides the frame size and exposure that decides the image's pixels: parts
// of one frame carry the same value and `zigzag merge` refuses to mix others.
std::string image_settings(const BatchOptions& o, const Scene& scene) {
  const RenderOptions& r = o.render;
  nlohmann::json j = {{"aa", r.aa}, {"max_depth", scene.max_depth}};
  if (r.aa == "adaptive")
    j["adaptive"] = {{"eps", r.eps}, {"tables", r.tables}, {"geo_policy", r.geo_policy}, {"filter", r.filter},
                     {"edges", r.edges}};
  if (wants_visibility_map(r)) j["edge"] = {{"ss", r.edge_ss}, {"angle", r.edge_angle}, {"depth", r.edge_depth}};
  if (r.aa == "uniform") j["uniform"] = {{"spp", r.spp}, {"pattern", r.pattern}};
  return j.dump();
}

bool wants_geo_map(const BatchOptions& o) {
  if (wants_visibility_map(o.render)) return true;
  for (const auto& aov : o.aovs)
    if (aov.first == "geo" && o.render.edges == "vulkan") return true;
  return false;
}

// Progress on stderr: a live bar on a terminal, nothing per tile otherwise.
class Progress {
 public:
  Progress(int tiles, bool live) : tiles_(tiles), live_(live), start_(std::chrono::steady_clock::now()) {}
  void tile_done(uint64_t tile_rays) {
    const int done = ++done_;
    const uint64_t rays = rays_ += tile_rays;
    if (!live_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const double t = seconds_since(start_);
    const double eta = done > 0 ? t * (tiles_ - done) / done : 0.0;
    const double mrays_per_s = t > 0.0 ? double(rays) / t * 1e-6 : 0.0;
    const int width = 30, filled = tiles_ > 0 ? width * done / tiles_ : width;
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d tiles  %.1f Mrays/s  %.1fs  ETA %.1fs ", filled,
                 "##############################", width - filled, "", done, tiles_, mrays_per_s, t, eta);
    if (done == tiles_) std::fprintf(stderr, "\r%*s\r", 90, "");
  }

 private:
  int tiles_;
  bool live_;
  std::atomic<int> done_{0};
  std::atomic<uint64_t> rays_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
};

void render_job(const BatchOptions& o, const std::filesystem::path& scene_path, VulkanContext* vulkan) {
  LoadOptions load;
  load.assets_dir = o.render.assets;
  load.quiet = o.quiet;
  auto t = std::chrono::steady_clock::now();
  Scene scene = load_scene(scene_path, load);
  if (o.render.max_depth >= 0) scene.max_depth = o.render.max_depth;
  const double load_s = seconds_since(t);
  const std::string scene_name = scene_path.stem().string();

  std::vector<int> cameras;
  if (o.camera == "all") {
    for (size_t i = 0; i < scene.cameras.size(); ++i) cameras.push_back(int(i));
  } else {
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
    cameras.push_back(index);
  }

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
    const std::string frame = o.region.empty()
                                  ? "a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) + " frame"
                                  : "a " + std::to_string(region.width()) + "x" + std::to_string(region.height()) +
                                        " region";
    // A region's film is region-sized, but the visibility map still covers the frame.
    const uint64_t full_geo_map = visibility ? uint64_t(settings.width) * uint64_t(settings.height) : 0;
    check_memory(frame_bytes(region.width(), region.height(),
                             settings.threads > 0 ? settings.threads : int(std::thread::hardware_concurrency())) +
                     full_geo_map,
                 frame.c_str());
    const std::string camera_name = std::to_string(camera_index);
    const std::string default_output = o.camera == "all" ? "{scene}_{camera}.png" : "{scene}.png";
    const std::filesystem::path output = expand_pattern(o.output.empty() ? default_output : o.output, scene_name, camera_name);

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
               {{"scene", scene_name}, {"camera", camera_name}, {"settings", image_settings(o, scene)}});
    const double write_s = seconds_since(t);
    const double pixels = double(region.width()) * region.height();
    const double rays_per_pixel = double(stats.rays.primary) / pixels;
    const GeoMap region_geo = film.is_region() ? crop(geo, region) : GeoMap{};
    for (const auto& [name, file] : o.aovs)
      write_aov(name, expand_pattern(file, scene_name, camera_name), film, film.is_region() ? region_geo : geo);

    nlohmann::json j;
    j["scene"] = scene_name;
    j["camera"] = camera_index;
    j["output"] = output.string();
    j["width"] = settings.width;
    j["height"] = settings.height;
    j["region"] = {region.x0, region.y0, region.x1, region.y1};
    j["pixels"] = region.width() * int64_t(region.height());
    j["threads"] = settings.threads > 0 ? settings.threads : int(std::thread::hardware_concurrency());
    j["aa"] = o.render.aa;
    if (o.render.aa == "uniform") {
      j["spp"] = o.render.spp;
      j["pattern"] = o.render.pattern;
    }
    if (o.render.aa == "adaptive") {
      const AaStats& a = stats.aa;
      j["adaptive"] = {{"eps", o.render.eps},
                       {"tables", o.render.tables},
                       {"geo_policy", o.render.geo_policy},
                       {"filter", o.render.filter},
                       {"by_level", {a.per_pixel(a.rays[0]), a.per_pixel(a.rays[1]), a.per_pixel(a.rays[2])}},
                       {"level2_fraction", a.level2_fraction()},
                       {"level3_fraction", a.level3_fraction()},
                       {"vertical_fraction", a.per_pixel(a.vertical_pixels)},
                       {"zones_traced", a.zones_traced},
                       {"zones_interpolated", a.zones_interpolated},
                       {"margin_rays", a.margin_rays},
                       {"geo_fraction", a.per_pixel(a.geo_pixels)},
                       // Summed over tiles (CPU seconds across threads): the split of render time.
                       {"time_s", {{"level1_corners", a.seconds_corners},
                                   {"levels_2_3", a.seconds_refine},
                                   {"mitchell_filter", a.seconds_filter}}}};
    }
    j["triangles"] = scene.triangle_count();
    j["dropped_degenerate_triangles"] = scene.dropped_degenerate;
    j["lights"] = scene.lights.size();
    j["max_depth"] = scene.max_depth;
    j["effects"] = shader.effects().names();
    j["rays_per_pixel"] = rays_per_pixel;
    j["rays"] = {{"primary", stats.rays.primary},
                 {"shadow", stats.rays.shadow},
                 {"reflection", stats.rays.reflection},
                 {"refraction", stats.rays.refraction},
                 {"total", stats.rays.total()}};
    j["bvh"] = {{"nodes", bvh_stats.node_count},
                {"leaves", bvh_stats.leaf_count},
                {"max_depth", bvh_stats.max_depth},
                {"sah_cost", bvh_stats.sah_cost},
                {"build_s", bvh_stats.build_seconds}};
    const double job_s = seconds_since(t_job) + (camera_index == cameras.front() ? load_s + bvh_s : 0.0);
    const double edges_s = visibility ? edge_times.total_s : 0.0;
    j["time_s"] = {{"load", load_s}, {"bvh", bvh_s}, {"render", stats.render_seconds}, {"write", write_s}, {"total", job_s}};
    j["edges"] = o.render.edges;
    if (visibility) {
      size_t flagged = 0;
      for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x) flagged += geo.at(x, y);
      j["time_s"]["edges"] = {{"upload", visibility->upload_seconds()},
                              {"raster", edge_times.raster_s},
                              {"compute", edge_times.compute_s},
                              {"readback", edge_times.readback_s},
                              {"total", edge_times.total_s}};
      j["geo_fraction"] = double(flagged) / pixels;
      j["edge_settings"] = {{"supersample", o.render.edge_ss}, {"normal_angle_deg", o.render.edge_angle}, {"depth_rel", o.render.edge_depth}};
      j["vulkan_device"] = vulkan->device_name();
    }
    j["mrays_per_s"] = stats.render_seconds > 0 ? double(stats.rays.total()) / stats.render_seconds * 1e-6 : 0.0;
    if (!o.stats.empty()) {
      const std::filesystem::path stats_path = expand_pattern(o.stats, scene_name, camera_name);
      if (stats_path.has_parent_path()) std::filesystem::create_directories(stats_path.parent_path());
      std::ofstream f(stats_path);
      f << j.dump(2) << "\n";
      if (!f) throw Error("cannot write " + stats_path.string());
    }
    if (!o.quiet) {
      std::string effects;
      for (const std::string& e : shader.effects().names()) effects += (effects.empty() ? "" : ",") + e;
      std::fprintf(stderr,
                   "%s cam %d: %dx%d%s aa=%s %.2f rays/px (%.2f total) effects=[%s] render %.2fs (%.1f Mrays/s) "
                   "edges %.2fs load %.2fs bvh %.2fs -> %s\n",
                   scene_name.c_str(), camera_index, settings.width, settings.height,
                   film.is_region() ? (" region " + o.region).c_str() : "", o.render.aa.c_str(), rays_per_pixel,
                   double(stats.rays.total()) / pixels, effects.c_str(), stats.render_seconds,
                   j["mrays_per_s"].get<double>(), edges_s, load_s, bvh_s, output.string().c_str());
    }
  }
}

}  // namespace

void add_render_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BatchOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render scene files (.json rig, .gltf, .glb) to images");
  cmd->add_option("scenes", o->scenes, "Scene files")->required();
  cmd->add_option("-o,--output", o->output,
                  "Output image; {scene} and {camera} are replaced (.png = display, .exr = linear HDR)");
  cmd->add_option("--stats", o->stats, "Write JSON stats per job ({scene}/{camera} patterns allowed)");
  cmd->add_option("--camera", o->camera, "Camera index, or 'all'");
  cmd->add_option("--aov", o->aovs, "Write an AOV image: --aov rays|levels|geo FILE.png (repeatable)");
  cmd->add_option("--region", o->region,
                  "Render only pixels X0,Y0,X1,Y1 (half-open): an EXR keeps the frame as display window, a PNG "
                  "is region-sized; parts merge with `zigzag merge`");
  add_render_options(cmd, o->render);
  cmd->add_flag("-q,--quiet", o->quiet, "No progress or summary on stderr");
  cmd->callback([o, &exit_code] {
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
