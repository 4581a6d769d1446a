// Scenes and checks shared by the robustness tests: scenes built in code at any scale
// and offset, a whole-frame render, and the "no NaN / Inf / negative" check.
#pragma once

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "../render/test_render.h"
#include "../render/test_scenes.h"
#include "accel/bvh.h"
#include "render/image_io.h"
#include "render/renderer.h"

namespace zz::robust {

using test::render;

inline RenderSettings settings(int w, int h, AaMode aa, int threads = 0) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.aa = aa;
  s.threads = threads;
  return s;
}

// Number of radiance values that are NaN, infinite or negative.
inline size_t bad_values(const Film& film) {
  size_t bad = 0;
  for (const glm::vec3& c : film.radiance)
    for (int i = 0; i < 3; ++i) bad += !std::isfinite(c[i]) || c[i] < 0.0f;
  return bad;
}

using test::bit_identical;

// A point mapped by p' = scale * p + offset, computed in double and rounded once.
struct Placement {
  double scale = 1.0;
  glm::dvec3 offset{0.0};
  glm::vec3 operator()(glm::vec3 p) const { return glm::vec3(scale * glm::dvec3(p) + offset); }
};

// Shadow test scene, 20 x 20 units: a grey floor (z = 0) with a box standing on it, lit
// by one point light, seen obliquely from above. Placing it scales every length (the
// light's intensity by scale^2, so radiance I / d^2 is unchanged) and moves it; the
// camera keeps its orientation. Ideal rendering gives the same image for any placement.
inline Scene shadow_scene(const Placement& at) {
  Scene s;
  s.name = "shadow";
  s.materials.push_back(test::diffuse_material(glm::vec3(0.7f)));
  s.materials.push_back(test::diffuse_material(glm::vec3(0.3f, 0.5f, 0.8f)));
  const glm::vec3 f[4] = {{-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}};
  test::add_quad(s, at(f[0]), at(f[1]), at(f[2]), at(f[3]), 0);
  Scene box;
  test::add_box(box, {-1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 1.5f}, 1);
  for (size_t t = 0; t < box.triangle_count(); ++t)
    test::add_triangle(s, at(box.positions[3 * t]), at(box.positions[3 * t + 1]), at(box.positions[3 * t + 2]), 1);
  Light light;
  light.position = at({3.0f, 2.0f, 4.0f});
  light.intensity = glm::vec3(float(60.0 * at.scale * at.scale));
  s.lights.push_back(light);
  s.background = glm::vec3(0.2f, 0.3f, 0.5f);
  Camera cam = Camera::look_at({0.0f, -7.0f, 6.0f}, {0.5f, 0.5f, 0.0f}, {0, 0, 1}, 0.9f);
  cam.position = at({0.0f, -7.0f, 6.0f});
  s.cameras.push_back(cam);
  s.max_depth = 1;
  s.finalize_materials();
  return s;
}

// A quad of `emission` filling the view (no lights): every pixel sees the same radiance.
inline Scene emissive_wall(glm::vec3 emission) {
  Scene s;
  Material m = test::diffuse_material(glm::vec3(0.0f));
  m.emissive = emission;
  s.materials.push_back(m);
  test::add_quad(s, {-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}, 0);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.max_depth = 0;
  s.finalize_materials();
  return s;
}

}  // namespace zz::robust
