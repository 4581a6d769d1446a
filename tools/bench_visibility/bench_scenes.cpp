#include "bench_scenes.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "scene/loader.h"
#include "scene/scene_builder.h"

namespace zz::bench {
namespace {

Scene finish(SceneBuilder& b, const std::string& name, const Camera& camera) {
  b.scene.name = name;
  b.scene.cameras[0] = camera;
  return b.done();
}

}  // namespace

Scene generated_scene(const std::string& name, int triangles) {
  SceneBuilder b;
  int per_sphere = triangles / 8;
  int slices = std::max(8, int(std::sqrt(double(per_sphere))));
  for (int k = 0; k < 6; ++k)
    b.sphere({-2.5f + k * 1.0f, 0.0f, -0.6f * (k % 3)}, 0.45f, slices, slices / 2);
  for (int k = 0; k < 5; ++k) b.box({-2.2f + k, -0.5f, 0.8f}, {-1.7f + k, 0.2f + 0.1f * k, 1.2f});
  b.box({-4.0f, -0.6f, -4.0f}, {4.0f, -0.5f, 4.0f});
  return finish(b, name, Camera::look_at({0.0f, 1.5f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f));
}

Scene sphere_scene(int slices) {
  SceneBuilder b;
  b.sphere({0.0f, 0.0f, 0.0f}, 1.0f, slices, slices / 2);
  return finish(b, "sphere" + std::to_string(slices), Camera::look_at({0.3f, 0.4f, 3.2f}, {0, 0, 0}, {0, 1, 0}, 0.8f));
}

Scene scene_or_fallback(const std::string& path, const std::string& name) {
  try {
    LoadOptions options;
    options.quiet = true;
    Scene s = load_scene(path, options);
    if (s.cameras.empty()) throw Error("no camera");
    return s;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s; using a generated stand-in\n", path.c_str(), e.what());
    return generated_scene(name);
  }
}

}  // namespace zz::bench
