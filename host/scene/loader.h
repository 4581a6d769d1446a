// Scene loading: our JSON scene files (scenes/*.json) and glTF 2.0 (.gltf / .glb).
// Every failure is a zz::Error with a one-line message naming the file and problem.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace zz {

struct LoadOptions {
  // Where third-party models referenced as "assets:NAME/..." are found; empty means
  // $ZIGZAG_ASSETS, else ../shared/scenes next to the project checkout.
  std::filesystem::path assets_dir;
  bool quiet = false;  // no warnings on stderr
};

Scene load_scene(const std::filesystem::path& path, const LoadOptions& options = {});

// Loads only the glTF part (used by load_scene for .gltf/.glb and by JSON rigs).
void load_gltf_into(Scene& scene, const std::filesystem::path& path, const glm::mat4& transform,
                    const LoadOptions& options);

}  // namespace zz
