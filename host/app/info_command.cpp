// `zigzag info SCENE... [--json]`: what a render of each scene would be — frame size,
// cameras, frame clock and range, size of the geometry — so a farm can plan its jobs
// without rendering. A scene that fails to load is reported and the others still are.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "app/json_text.h"
#include "app/option_checks.h"
#include "app/commands.h"
#include "scene/camera_select.h"
#include "scene/loader.h"

namespace zz {

namespace {

struct InfoOptions {
  std::vector<std::string> scenes;
  bool json = false;
  double fps = 0.0;
  std::string assets;
  int width = 0, height = 0;  // as `render --width/--height` would be given (0: the scene's)
};

nlohmann::json scene_info(const std::filesystem::path& path, const InfoOptions& o) {
  LoadOptions load;
  load.assets_dir = o.assets;
  load.quiet = true;
  load.allow_missing_textures = true;  // describes the geometry whatever its textures
  load.fps = o.fps;
  const Scene scene = load_scene(path, load);
  nlohmann::json cameras = nlohmann::json::array(), sizes = nlohmann::json::array();
  for (const Camera& c : scene.cameras) {
    cameras.push_back(c.name);
    const FrameSize size = frame_size(scene, c, o.width, o.height);  // what `render --camera N` uses
    sizes.push_back({size.width, size.height});
  }
  const FrameSize size = frame_size(scene, scene.cameras.front(), o.width, o.height);
  return {{"path", path.string()},
          {"scene", path.stem().string()},  // what {scene} expands to in output patterns
          {"name", scene.name},
          {"width", size.width},  // of camera 0, the default
          {"height", size.height},
          {"cameras", cameras},
          {"camera_sizes", sizes},
          {"camera_count", scene.cameras.size()},
          {"animated", scene.animated},
          {"animation_end_s", scene.animation_end},
          {"fps", scene.fps},
          {"frames", {scene.first_frame, scene.last_frame}},
          {"frame_count", scene.last_frame - scene.first_frame + 1},
          {"triangles", scene.triangle_count()},
          {"lights", scene.lights.size()},
          {"files", scene.source_files}};
}

void print_human(const nlohmann::json& j) {
  std::string cameras;
  for (size_t i = 0; i < j["cameras"].size(); ++i) {
    const auto& size = j["camera_sizes"][i];
    cameras += (i == 0 ? "" : ", ") + j["cameras"][i].get<std::string>() + " (" + std::to_string(size[0].get<int>()) +
               "x" + std::to_string(size[1].get<int>()) + ")";
  }
  std::printf("%s (%s)\n", j["scene"].get<std::string>().c_str(), j["path"].get<std::string>().c_str());
  std::printf("  size      %dx%d\n", j["width"].get<int>(), j["height"].get<int>());
  std::printf("  cameras   %zu: %s\n", j["cameras"].size(), cameras.c_str());
  if (j["animated"].get<bool>())
    std::printf("  animation %.3f s, frames %d..%d (%d) at %g fps\n", j["animation_end_s"].get<double>(),
                j["frames"][0].get<int>(), j["frames"][1].get<int>(), j["frame_count"].get<int>(), j["fps"].get<double>());
  else
    std::printf("  animation none (frames %d..%d at %g fps)\n", j["frames"][0].get<int>(), j["frames"][1].get<int>(),
                j["fps"].get<double>());
  std::printf("  geometry  %zu triangles, %zu lights\n", j["triangles"].get<size_t>(), j["lights"].get<size_t>());
  std::printf("  files    ");
  for (const auto& f : j["files"]) std::printf(" %s", f.get<std::string>().c_str());
  std::printf("\n");
}

}  // namespace

void add_info_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand("info", "Describe scenes: frame size, cameras, frame range, geometry");
  cmd->add_option("scenes", o->scenes, "Scene files")->required();
  cmd->add_flag("--json", o->json, "A JSON array, one object per scene (failed scenes have \"error\")");
  cmd->add_option("--fps", o->fps, "Frames per second for the frame range (default: the rig's, else 24)")
      ->check(number_in(1e-3, 1000.0));
  cmd->add_option("--width", o->width, "Image width the sizes are for, as render --width (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  cmd->add_option("--height", o->height, "Image height the sizes are for, as render --height (default: the scene's)")
      ->check(CLI::Range(1, kMaxImageSide));
  add_assets_option(cmd, o->assets);
  cmd->callback([o, &exit_code] {
    nlohmann::json all = nlohmann::json::array();
    int failed = 0;
    for (const std::string& path : o->scenes) {
      try {
        all.push_back(scene_info(path, *o));
        if (!o->json) print_human(all.back());
      } catch (const std::exception& e) {
        const std::string what = error_text(e);
        std::fprintf(stderr, "zigzag: error: %s\n", what.c_str());
        all.push_back({{"path", path}, {"error", what}});
        ++failed;
      }
    }
    if (o->json) std::printf("%s\n", json_text(all, 2).c_str());
    exit_code = failed > 0 ? 1 : 0;
  });
}

}  // namespace zz
