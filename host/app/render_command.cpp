// `zigzag render SCENE... [options]`: headless batch rendering to PNG/EXR + JSON stats.
// Every option is checked before the first scene is loaded; after that, one failed job
// is reported and the others still run; the exit code says whether any failed.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "aa/adaptive_sampler.h"
#include "accel/bvh.h"
#include "app/batch_options.h"
#include "app/commands.h"
#include "app/json_text.h"
#include "app/output_paths.h"
#include "app/progress.h"
#include "app/render_stats_json.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "scene/camera_select.h"
#include "scene/scene_files.h"
#include "gpu/device.h"
#include "gpu/visibility.h"
#include "render/aov.h"
#include "render/film_merge.h"
#include "render/image_io.h"
#include "render/memory_budget.h"
#include "render/primary_hits.h"
#include "render/renderer.h"
#include "render/see_through.h"  // the layer limits the warning names
#include "scene/loader.h"

namespace zz {

namespace {

std::vector<int> select_cameras(const BatchOptions& o, const Scene& scene, const std::filesystem::path& scene_path) {
  std::vector<int> cameras;
  if (o.all_cameras()) {
    for (size_t i = 0; i < scene.cameras.size(); ++i) cameras.push_back(int(i));
    return cameras;
  }
  try {
    return {int(find_camera(scene, o.camera))};
  } catch (const Error& e) {
    throw Error(scene_path.string() + ": --camera " + o.camera + ": " + e.what() + " (or use all)");
  }
}

// Everything besides the frame size and exposure that decides the image's pixels: the
// parts of one frame carry the same value, and `zigzag merge` refuses to mix others.
std::string image_settings(const BatchOptions& o, const Scene& scene) {
  const RenderOptions& r = o.render;
  nlohmann::json j = {{"aa", name_of(kAaModes, r.aa)}, {"max_depth", scene.max_depth}, {"time", scene.time}};
  if (r.aa == AaMode::Adaptive) {
    j["adaptive"] = adaptive_settings_json(r.adaptive);
    j["adaptive"]["edges"] = name_of(kEdgeModes, r.edges);
  }
  if (wants_geo_map(o)) j["edge"] = {{"ss", r.edge_ss}, {"angle", r.edge_angle}, {"depth", r.edge_depth}, {"material", r.edge_material}};
  if (r.aa == AaMode::Uniform) j["uniform"] = {{"spp", r.spp}, {"pattern", name_of(kUniformPatterns, r.pattern)}};
  return j.dump();
}

// The loaded frame, or for a --time the frame at that time (frame_at, whose time the
// loader made exact); none for a time between frames.
std::optional<int> whole_frame(const Scene& scene) {
  if (scene.frame >= 0) return scene.frame;
  return frame_at(scene.time, scene.fps);
}

// The frame number {frame} names: whole_frame. A time between frames names none, so a
// pattern with {frame} is refused there: rounding it would let two times overwrite one file.
int output_frame(const BatchOptions& o, const Scene& scene) {
  if (const std::optional<int> frame = whole_frame(scene)) return *frame;
  const double at = scene.time * scene.fps;
  for (const OutputPattern& p : output_patterns(o))
    if (p.pattern.find("{frame") != std::string::npos) {
      char when[160];
      std::snprintf(when, sizeof when, "--time %.9g is %s (frame %.9g at %g fps)", scene.time,
                    at > kMaxFrame ? "past the last frame number" : "between frames", at, scene.fps);
      throw UsageError(std::string(when) + ", so {frame} in " + p.option + " " + p.pattern +
                       " names no frame: give --frame N, or an output name without {frame}");
    }
  return 0;  // no name holds it
}

std::string seconds_text(double s) {
  char text[48];
  std::snprintf(text, sizeof text, "%g s", s);
  return text;
}

// A batch's jobs (one per scene and camera) and those that failed; refused: the job's
// options cannot work for its scene (UsageError), which a farm must not run again.
struct JobTally {
  int jobs = 0, failed = 0, refused = 0;

  // `where` names the job ("scene.json: camera 1") unless the message starts with it.
  void fail(const std::string& scene_and_camera, const std::exception& e) {
    const std::string what = one_line(error_text(e)), where = one_line(scene_and_camera);  // as zz::Error quotes
    const bool named = where.empty() || what.rfind(where, 0) == 0;
    std::fprintf(stderr, "zigzag: error: %s%s\n", named ? "" : (where + ": ").c_str(), what.c_str());
    ++failed;
    refused += dynamic_cast<const UsageError*>(&e) != nullptr;
  }
};

// The batch's Vulkan device, created on a thread of its own from the start, so that it
// overlaps the first scene's load; get() waits for it (main thread only). A failure to
// create it ends the whole batch (failed()), even after a job failed to load: it says what
// to install.
class DeviceSource {
 public:
  // An invalid future: no map wanted, get() is null.
  explicit DeviceSource(std::future<std::unique_ptr<VulkanContext>> creating) : creating_(std::move(creating)) {}

  VulkanContext* get() {
    if (error_) std::rethrow_exception(error_);
    if (creating_.valid()) {
      try {
        context_ = creating_.get();
      } catch (...) {
        error_ = std::current_exception();
        throw;
      }
    }
    return context_.get();
  }
  bool failed() const { return error_ != nullptr; }

 private:
  std::future<std::unique_ptr<VulkanContext>> creating_;
  std::unique_ptr<VulkanContext> context_;
  std::exception_ptr error_;
};

// A scene's visibility pass, made by its first frame's map thread: the scene's upload then
// runs beside level 1's corner rays instead of before them. The device is waited for
// before the frame (render_job), so that the memory estimate holds what it made resident.
class SceneMap {
 public:
  SceneMap(VulkanContext& vulkan, const Scene& scene) : vulkan_(vulkan), scene_(scene) {}

  struct Use {
    VisibilityPass& pass;
    double upload_s;  // the upload this call made (0 once made)
  };
  // A failed upload (a scene past the storage-buffer range, say) fails every camera with
  // the same error, without uploading again.
  Use get() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (error_) std::rethrow_exception(error_);
    if (pass_) return {*pass_, 0.0};
    try {
      pass_ = std::make_unique<VisibilityPass>(vulkan_, scene_);
    } catch (...) {
      error_ = std::current_exception();
      throw;
    }
    return {*pass_, pass_->upload_seconds()};
  }
  // Memory the pass will take that is not resident yet (the memory estimate's share).
  uint64_t bytes_to_come() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return pass_ || error_ ? 0 : VisibilityPass::scene_bytes(scene_.positions.size() / 3);
  }
  const VulkanContext& vulkan() const { return vulkan_; }

 private:
  VulkanContext& vulkan_;
  const Scene& scene_;
  std::mutex mutex_;
  std::unique_ptr<VisibilityPass> pass_;
  std::exception_ptr error_;
};

// What a scene's cameras share: loaded, posed, its BVH built and its map pass made once.
struct SceneJob {
  const Scene& scene;
  std::string name;  // the file's stem, {scene}
  int frame;         // {frame}
  const Shader& shader;
  const BvhBuildStats& bvh_stats;
  SceneMap* map;                 // null: no visibility map
  double load_s, bvh_s;          // counted in the first camera's total
  double device_wait_s;          // the wait for the device that the load and BVH did not hide (idem)
  const std::vector<std::string>& batch_inputs;  // every scene's files, listed before the first loaded
  OutputClaims& claims;                          // the files the batch's jobs so far write
  std::string files_fingerprint;                 // of the files as loaded, for EXR outputs; empty without
};

void render_camera(const BatchOptions& o, const SceneJob& job, int camera_index, bool first_camera);

// `device` yields the Vulkan context (null: no map wanted); it may still be being created.
// A camera whose job fails is reported and the scene's other cameras still render.
void render_job(const BatchOptions& o, const std::filesystem::path& scene_path, const std::vector<std::string>& inputs,
                DeviceSource& device, OutputClaims& claims, JobTally& tally) {
  const LoadOptions load = load_options(o.render, o.quiet);
  auto t = std::chrono::steady_clock::now();
  Scene scene = load_scene(scene_path, load);
  if (o.render.max_depth >= 0) scene.max_depth = o.render.max_depth;
  // Hashed now, not as each camera's EXR is written: a file saved anew during a long
  // render must not stamp the parts rendered from its old version with its new bytes.
  const std::string fingerprint =
      holds_extra_channels(o.output_pattern()) ? files_fingerprint(scene.source_files) : std::string();
  const double load_s = seconds_since(t);
  const std::string scene_name = scene_path.stem().string();
  const std::vector<int> cameras = select_cameras(o, scene, scene_path);
  const int frame = output_frame(o, scene);
  warn_outside_animation(scene, o.quiet);

  t = std::chrono::steady_clock::now();
  BvhBuildStats bvh_stats;
  const Bvh bvh = Bvh::build(scene.positions, &bvh_stats);
  const double bvh_s = seconds_since(t);
  const Shader shader(scene, bvh);
  t = std::chrono::steady_clock::now();
  VulkanContext* vulkan = device.get();
  const double device_wait_s = seconds_since(t);
  std::optional<SceneMap> map;
  if (vulkan) map.emplace(*vulkan, scene);

  const SceneJob job{scene, scene_name, frame, shader, bvh_stats, map ? &*map : nullptr, load_s, bvh_s, device_wait_s, inputs, claims,
                     fingerprint};
  for (int camera_index : cameras) {
    ++tally.jobs;
    try {
      render_camera(o, job, camera_index, camera_index == cameras.front());
    } catch (const std::exception& e) {
      tally.fail(scene_path.string() + (cameras.size() > 1 ? ": camera " + std::to_string(camera_index) : ""), e);
    }
  }
}

void render_camera(const BatchOptions& o, const SceneJob& job, int camera_index, bool first_camera) {
  const Scene& scene = job.scene;
  const Shader& shader = job.shader;
  auto t = std::chrono::steady_clock::now();
  const auto t_job = t;
  RenderSettings settings = make_render_settings(o.render, scene, scene.cameras[size_t(camera_index)]);
  if (!o.region.empty()) settings.region = parse_region(o.region);
  const TileRect region = render_region(settings);
  // A region's sampler reads the map beyond the region: its filter margin and the gaps' ring.
  std::optional<TileRect> map_region;
  if (!o.region.empty()) map_region = adaptive_geo_reads(region, settings.width, settings.height, settings.adaptive);
  const VisibilitySettings map_settings = make_visibility_settings(o.render);
  const std::string what = o.region.empty() ? "a " + std::to_string(settings.width) + "x" +
                                                   std::to_string(settings.height) + " frame"
                                             : "a " + std::to_string(region.width()) + "x" +
                                                   std::to_string(region.height()) + " region";
  // The film's own memory (region-sized; display image, scratch, the region's map), the
  // visibility raster and readback (full-frame tiles, the region's flags, and for a region
  // the full-size map run() returns beside it), the scene's upload on its first frame (the
  // map's thread makes it), and the level-1 corner field on top of what the process holds
  // now (libraries, Vulkan, scene, BVH).
  uint64_t frame_need = render_bytes(settings, region, scene);
  if (job.map)
    frame_need += job.map->bytes_to_come() +
                  VisibilityPass::frame_bytes(settings.width, settings.height, map_settings, scene.positions.size() / 3, map_region) +
                  (map_region ? uint64_t(settings.width) * uint64_t(settings.height) : 0);
  // Multi-layer EXR: the channels (4 bytes each), one band of the interleaved write,
  // and the primary hits (depth + normal + albedo: 28 bytes) when traced.
  size_t layer_count = 0;
  for (Aov a : o.layer_aovs()) layer_count += aov_channel_names(a).size();
  const uint64_t region_pixels = uint64_t(region.width()) * uint64_t(region.height());
  const uint64_t layer_need = layer_count == 0 ? 0
                                               : region_pixels * (4 * layer_count + (o.wants_primary_hits() ? 28 : 0)) +
                                                     uint64_t(64) * uint64_t(region.width()) * 4 * (3 + layer_count);
  frame_need += layer_need;
  check_memory(frame_need, what.c_str());
  if (job.map)  // what the map's thread would find beside level 1, after seconds of work
    VisibilityPass::check_fits(job.map->vulkan(), scene.positions.size() / 3, settings.width, settings.height,
                               map_region);
  const uint64_t memory_estimate = resident_bytes() + frame_need;
  const OutputKey key{job.name, std::to_string(camera_index), job.frame};
  const std::filesystem::path output = expand_output_pattern(o.output_pattern(), key);
  job.claims.claim(output_patterns(o), key, "job " + job.name + " camera " + key.camera);
  for (const OutputPattern& p : output_patterns(o)) {
    const std::filesystem::path path = expand_output_pattern(p.pattern, key, p.option);
    // Again with this job's own frame and camera (the batch's check saw stand-ins: an
    // 8-digit {frame} can take a name past the file system's limit), before the render.
    preflight_output(p.option, path, p.option != "--stats");
    check_not_an_input(p.option, path, scene.source_files);
    check_not_an_input(p.option, path, job.batch_inputs, "a file of the batch's scenes,");
  }

  // The map is made on its own thread while level 1 traces (render_frame awaits it
  // before classifying); --edges-serial makes it first. The image is the same. The map's
  // one-off set-up runs on that thread too, inside the frame's clock: a scene's first
  // frame uploads the scene, and a frame of a new size allocates the targets and the
  // flag pipeline (prepare; room 1024^2: 0.1 s that preceded the frame on one core).
  const auto t_frame = std::chrono::steady_clock::now();
  GeoMap geo;
  VisibilityTimings edge_times;
  MapSetup setup;
  bool map_made = false;  // this frame has the map (a failed one throws before the stats)
  std::shared_future<GeoMap> pending;
  const GeoMap* map = &geo;  // the frame's map: geo, or the one pending made
  if (job.map) {
    auto make_map = [&, camera_index] {
      const auto t_map = std::chrono::steady_clock::now();
      const SceneMap::Use use = job.map->get();
      setup.upload_s = use.upload_s;
      const auto t_prepare = std::chrono::steady_clock::now();
      use.pass.prepare(settings.width, settings.height, map_settings, map_region,
                       scene.cameras[size_t(camera_index)].orthographic());
      setup.prepare_s = seconds_since(t_prepare);
      GeoMap made = use.pass.run(scene.cameras[size_t(camera_index)], settings.width, settings.height, map_settings,
                                 &edge_times, map_region);
      setup.total_s = seconds_since(t_map);
      map_made = true;
      return made;
    };
    if (o.render.edges_serial) geo = make_map();
    else pending = std::async(std::launch::async, make_map).share();
  }

  Film film;
  RenderStats stats;
  // Steps: the level-1 blocks traced before the tiles, then the tiles.
  Progress progress(int(corner_field_plan(settings).blocks + make_tiles(settings.width, settings.height, region, settings.tile_size).size()),
                    !o.quiet && isatty(STDERR_FILENO));
  RenderCallbacks callbacks;
  callbacks.tile_done = [&](const TileRect&, const RayCounters& rays) { progress.step_done(rays.total()); };
  callbacks.corners_done = [&](const RayCounters& rays) { progress.step_done(rays.total()); };
  callbacks.cancel = &interrupt_flag();
  {
    CancellableScope cancellable;  // SIGINT/SIGTERM stop the tiles; nothing is written
    if (pending.valid()) {
      render_frame(shader, scene.cameras[size_t(camera_index)], pending, settings, film, stats, callbacks);
      map = &pending.get();  // not a copy: a 16384^2 frame's map is 256 MiB
    } else {
      render_frame(shader, scene.cameras[size_t(camera_index)], geo, settings, film, stats, callbacks);
    }
  }
  throw_if_interrupted();
  const double frame_s = seconds_since(t_frame);

  // The AOV layers of the -o EXR (render/aov_layers.h); the centre rays only when
  // depth, normal or albedo is among them.
  const GeoMap region_geo = film.is_region() ? crop(*map, region) : GeoMap{};
  const GeoMap& film_geo = film.is_region() ? region_geo : *map;
  RayCounters aov_rays;
  double aov_s = 0.0;
  if (!o.layer_aovs().empty()) {
    t = std::chrono::steady_clock::now();
    PrimaryHits hits;
    if (o.wants_primary_hits()) {
      CancellableScope cancellable;
      hits = trace_primary_hits(shader, scene.cameras[size_t(camera_index)], settings.width, settings.height,
                                region, settings.threads, &interrupt_flag(), &aov_rays);
    }
    throw_if_interrupted();
    film.channels = aov_channels(o.layer_aovs(), film, film_geo, hits);
    aov_s = seconds_since(t);
  }

  // The job's files are published together once all are written (core/atomic_file.h).
  OutputSet outputs;
  t = std::chrono::steady_clock::now();
  FilmAttributes attributes{{"scene", job.name}, {"camera", key.camera}, {"settings", image_settings(o, scene)}};
  if (map_made) attributes[kDeviceAttribute] = job.map->vulkan().device_name();  // merge says when parts' differ
  if (holds_extra_channels(output))  // (a pattern whose extension is a placeholder is hashed here)
    attributes[kSceneFilesAttribute] =
        job.files_fingerprint.empty() ? files_fingerprint(scene.source_files) : job.files_fingerprint;
  write_film(output, film, settings.tonemap, attributes, &outputs);
  std::string written = output.string();  // for the summary line: the image, then the AOV images
  for (const AovRequest& a : o.aovs)
    if (!a.layers()) {
      const std::filesystem::path file = expand_output_pattern(a.file, key, "--aov");
      write_aov(a.aov, file, film, film_geo, &outputs);
      written += ", " + file.string();
    }
  // Every image; the stats file (which cannot hold its own time) and the renames follow.
  const double write_s = seconds_since(t);

  JobRecord record;
  record.scene_name = job.name;
  record.camera = camera_index;
  record.output = output.string();
  record.options = &o.render;
  record.settings = &settings;
  record.stats = &stats;
  record.scene = &scene;
  record.frame = whole_frame(scene);
  record.shader = &shader;
  record.bvh = &job.bvh_stats;
  record.memory_estimate_bytes = memory_estimate;
  record.region = region;
  for (const FilmChannel& c : film.channels) record.aov_channels.push_back(c.name);
  record.aov_rays = aov_rays;
  record.aov_seconds = aov_s;
  // The scene's load and BVH are the first camera's, in its total; a later camera's are 0
  // (as its map's upload is), so every camera's stages add up to its total.
  const double load_s = first_camera ? job.load_s : 0.0, bvh_s = first_camera ? job.bvh_s : 0.0;
  record.times = {load_s, bvh_s, write_s,
                  seconds_since(t_job) + (first_camera ? job.load_s + job.bvh_s + job.device_wait_s : 0.0), frame_s};
  if (map_made) {
    setup.device_wait_s = first_camera ? job.device_wait_s : 0.0;
    record.map_setup = setup;
    record.edge_times = &edge_times;
    record.geo = map;
    record.vulkan_device = job.map->vulkan().device_name();
  }
  const nlohmann::json j = render_stats_json(record);
  if (stats.rays.nan_radiance > 0)
    std::fprintf(stderr,
                 "zigzag: warning: %s camera %d: %llu traced samples came out NaN and were set to black; "
                 "this is a renderer bug, please report it with the scene\n",
                 job.name.c_str(), camera_index, static_cast<unsigned long long>(stats.rays.nan_radiance));
  if (stats.rays.capped_radiance > 0 && !o.quiet)
    std::fprintf(stderr,
                 "zigzag: warning: %s camera %d: %llu traced samples came out brighter than 1e30 (or infinite) and "
                 "were capped there; is a light almost on a surface?\n",
                 job.name.c_str(), camera_index, static_cast<unsigned long long>(stats.rays.capped_radiance));
  if (stats.rays.layer_limit > 0 && !o.quiet)
    std::fprintf(stderr,
                 "zigzag: warning: %s camera %d: %llu rays met more than %d alpha cut-outs or %d blended surfaces one "
                 "behind another; what lay further behind is left out of them\n",
                 job.name.c_str(), camera_index, static_cast<unsigned long long>(stats.rays.layer_limit),
                 kMaxSeeThroughLayers, kMaxBlendLayers);
  if (!o.stats.empty())
    write_text_atomically(expand_output_pattern(o.stats, key, "--stats"), json_text(j, 2) + "\n", &outputs);
  outputs.commit();
  if (!o.quiet) {
    std::string effects;
    for (const std::string& e : shader.effects().names()) effects += (effects.empty() ? "" : ",") + e;
    const double pixels = double(region.width()) * region.height();
    const std::string where = (film.is_region() ? " region " + o.region : std::string()) +
                              (!scene.animated      ? std::string()
                               : scene.frame >= 0   ? " frame " + std::to_string(job.frame)
                                                    : " time " + seconds_text(scene.time));
    std::fprintf(stderr,
                 "%s cam %d: %dx%d%s aa=%s %.2f rays/px (%.2f total) effects=[%s] render %.2fs (%.1f Mrays/s) "
                 "edges %.2fs load %.2fs bvh %.2fs -> %s\n",
                 job.name.c_str(), camera_index, settings.width, settings.height, where.c_str(),
                 name_of(kAaModes, o.render.aa),
                 j["rays_per_pixel"].get<double>(), double(stats.rays.total()) / pixels, effects.c_str(),
                 stats.render_seconds, j["mrays_per_s"].get<double>(), map_made ? setup.total_s : 0.0,
                 load_s, bvh_s, written.c_str());
  }
}

}  // namespace

void add_render_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BatchOptions>();
  auto dry_run = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("render", "Render scene files (.json rig, .gltf, .glb) to images");
  add_batch_options(cmd, *o);
  cmd->add_flag("--dry-run", *dry_run,
                "Check the options, that the scene files exist and the outputs as a render would before "
                "loading anything (exit 105 on a refusal, 1 for a missing scene), then exit without "
                "loading, rendering or writing");
  cmd->callback([o, dry_run, &exit_code, cmd] {
    std::vector<std::string> inputs;
    as_usage_checks([&] {  // before anything is loaded: a bad invocation costs no render
      validate(*o);
      inputs = batch_inputs(*o);
      preflight_outputs(*o, inputs);
    });
    if (!o->quiet)
      for (const std::string& w : inapplicable_options(*cmd, *o)) std::fprintf(stderr, "zigzag: warning: %s\n", w.c_str());
    if (*dry_run) {  // a farm checks a batch's command line so before it queues any job
      for (const std::string& scene : o->scenes)
        if (std::error_code ec; !std::filesystem::is_regular_file(scene, ec) || ::access(scene.c_str(), R_OK) != 0) {
          std::fprintf(stderr, "zigzag: error: %s: %s\n", scene.c_str(),
                       std::filesystem::exists(scene, ec) ? "not a readable file" : "no such file");
          exit_code = 1;  // as the render's job would fail
        }
      return;
    }
    // Instance and device creation overlap the first scene's load and BVH build; the
    // first job that needs the device waits for it. Creation errors (no device: the
    // install hint) end the whole batch as before, even after a job failed to load.
    std::future<std::unique_ptr<VulkanContext>> creating;
    if (wants_geo_map(*o)) {
      VulkanOptions vo;
      // Without Vulkan, --aov geo must go too: --edges off refuses it.
      if (wants_geo_aov(*o))
        vo.without_vulkan = wants_visibility_map(o->render) ? "drop --aov geo and run with --edges off" : "drop --aov geo";
      vo.device_index = o->render.vk_device;
      vo.validate = o->render.vk_validate;
      creating = std::async(std::launch::async, [vo] { return VulkanContext::create(vo); });
    }
    DeviceSource device(std::move(creating));
    JobTally tally;
    OutputClaims claims;
    for (const std::string& scene : o->scenes) {
      const int jobs_before = tally.jobs;
      try {
        render_job(*o, scene, inputs, device, claims, tally);
      } catch (const std::exception& e) {
        if (device.failed()) device.get();  // rethrows: no device ends the batch
        tally.jobs = jobs_before + 1;  // the scene failed before its cameras: one job
        tally.fail(scene, e);
      }
    }
    VulkanContext* vulkan = device.get();  // a batch whose jobs all failed before needing the device still reports it
    if (tally.failed > 0 && tally.jobs > 1)
      std::fprintf(stderr, "zigzag: %d of %d jobs failed\n", tally.failed, tally.jobs);
    // Only refusals: the usage exit code, so a farm does not run the jobs again.
    exit_code = tally.failed == 0 ? 0 : tally.refused == tally.failed ? kUsageExit : 1;
    if (vulkan) vulkan->close();  // objects left alive on the device are reported now, and counted
    if (vulkan && vulkan->validation_enabled() && vulkan->validation_message_count() > 0) {
      std::fprintf(stderr, "zigzag: %d Vulkan validation message(s)\n", vulkan->validation_message_count());
      exit_code = 1;
    }
  });
}

}  // namespace zz
