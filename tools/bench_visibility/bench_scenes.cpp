#include "bench_scenes.h"

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "scene/loader.h"

namespace zz::bench {
namespace {

struct Builder {
  Scene s;
  void tri(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    s.positions.insert(s.positions.end(), {a, b, c});
    glm::vec3 n = glm::cross(b - a, c - a);
    float l = glm::length(n);
    n = l > 0.0f ? n / l : glm::vec3(0, 0, 1);
    s.normals.insert(s.normals.end(), {n, n, n});
    s.uvs.insert(s.uvs.end(), 3, glm::vec2(0.0f));
    s.material_of.push_back(0);
  }
  void sphere(glm::vec3 c, float r, int slices) {
    int stacks = slices / 2;
    auto at = [&](int i, int j) {
      if (j == 0) return c + glm::vec3(0, r, 0);
      if (j == stacks) return c - glm::vec3(0, r, 0);
      double th = M_PI * j / stacks, ph = 2.0 * M_PI * (i % slices) / slices;
      return c + r * glm::vec3(glm::dvec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
    };
    for (int j = 0; j < stacks; ++j)
      for (int i = 0; i < slices; ++i) {
        if (j != 0) tri(at(i, j), at(i + 1, j), at(i + 1, j + 1));
        if (j != stacks - 1) tri(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      }
  }
  void box(glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 c[8];
    for (int i = 0; i < 8; ++i) c[i] = glm::vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& f : q) {
      tri(c[f[0]], c[f[1]], c[f[2]]);
      tri(c[f[0]], c[f[2]], c[f[3]]);
    }
  }
  Scene done(const std::string& name, Camera cam) {
    s.name = name;
    s.materials.push_back(Material{});
    s.finalize_materials();
    s.cameras.push_back(cam);
    return std::move(s);
  }
};

}  // namespace

Scene generated_scene(const std::string& name, int triangles) {
  Builder b;
  int per_sphere = triangles / 8;
  int slices = std::max(8, int(std::sqrt(double(per_sphere))));
  for (int k = 0; k < 6; ++k)
    b.sphere({-2.5f + k * 1.0f, 0.0f, -0.6f * (k % 3)}, 0.45f, slices);
  for (int k = 0; k < 5; ++k) b.box({-2.2f + k, -0.5f, 0.8f}, {-1.7f + k, 0.2f + 0.1f * k, 1.2f});
  b.box({-4.0f, -0.6f, -4.0f}, {4.0f, -0.5f, 4.0f});
  return b.done(name, Camera::look_at({0.0f, 1.5f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f));
}

Scene sphere_scene(int slices) {
  Builder b;
  b.sphere({0.0f, 0.0f, 0.0f}, 1.0f, slices);
  return b.done("sphere" + std::to_string(slices), Camera::look_at({0.3f, 0.4f, 3.2f}, {0, 0, 0}, {0, 1, 0}, 0.8f));
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
