// Scenes for the visibility benchmark and survey: a scene file when it loads, else a
// generated stand-in, so the tools always run.
#pragma once

#include <string>

#include "scene/scene.h"

namespace zz::bench {

// Loads `path` (zz::load_scene); on failure prints why and returns generated_scene(name).
Scene scene_or_fallback(const std::string& path, const std::string& name);
// Tessellated spheres, boxes and a floor, ~`triangles` triangles, with a camera.
Scene generated_scene(const std::string& name, int triangles = 20000);
// A finely tessellated sphere (slices x slices/2) filling most of the frame.
Scene sphere_scene(int slices);

}  // namespace zz::bench
