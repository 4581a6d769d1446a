// Scene loading: our JSON scene files (scenes/*.json) and glTF 2.0 (.gltf / .glb).
// Every failure is a zz::Error with a one-line message naming the file and problem.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace zz {

struct LoadOptions {
  LoadOptions() = default;
  LoadOptions(std::filesystem::path assets, bool quiet_) : assets_dir(std::move(assets)), quiet(quiet_) {}

  // Where third-party models referenced as "assets:NAME/..." are found; empty means
  // $ZIGZAG_ASSETS, else ../shared/scenes next to the project checkout.
  std::filesystem::path assets_dir;
  bool quiet = false;  // no warnings on stderr
  // A texture whose image is missing, unreadable or out of range is an error naming it,
  // unless allowed: then the material is rendered without it, with a warning.
  bool allow_missing_textures = false;
  // When to load an animated scene: `time` seconds, else `frame` / fps, else the first
  // frame of the scene's range. fps: this if > 0, else the rig's "fps", else 24.
  std::optional<double> time;
  std::optional<int> frame;
  double fps = 0.0;
};

inline constexpr double kDefaultFps = 24.0;

Scene load_scene(const std::filesystem::path& path, const LoadOptions& options = {});

// The files loading `path` would read (the rig, its glTF, the glTF's buffers and images),
// from their JSON alone, without loading the scene: a batch checks its outputs against
// every scene's files before it renders the first. Never throws; a file it cannot read
// ends the list, and loading says why.
std::vector<std::string> scene_files(const std::filesystem::path& path, const LoadOptions& options = {});

// A camera that frames the bounding sphere of the scene's triangles, looking from the
// front (+Z), slightly right and above; used when neither the rig nor the model has one.
Camera auto_camera(const Scene& scene, float yfov = 0.8f);

// The lights a glTF loaded directly gets when it has none (with a warning): a directional
// headlight along the camera's view (1 lux) and a directional key light from above, right
// and in front of the model (2 lux). A rig's lights are its own: a rig never gets these.
std::vector<Light> default_lights(const Camera& camera);

// Throws a zz::Error naming `file` when the scene has no triangles (a black image is not
// a result).
void require_triangles(const Scene& scene, const std::string& file);

// Loads only the glTF part (used by load_scene for .gltf/.glb and by JSON rigs), with
// animated nodes posed at options.time (seconds; unset = 0).
// Appends triangles, materials, textures, lights and cameras (all moved by `transform`);
// does not finalize materials nor add an auto camera.
void load_gltf_into(Scene& scene, const std::filesystem::path& path, const glm::mat4& transform,
                    const LoadOptions& options);

}  // namespace zz
