// A brute-force first-hit reference for the gpu tests (scenes: scene/scene_builder.h).
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "scene/scene_builder.h"

namespace zz::test {

using zz::SceneBuilder;

// First hit along o + t d (t > 0) over all triangles, Moller & Trumbore 1997 in double;
// returns triangle index + 1, 0 for a miss.
inline uint32_t first_hit(const Scene& scene, glm::dvec3 o, glm::dvec3 d, double* t_hit = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  uint32_t id = 0;
  size_t n = scene.positions.size() / 3;
  for (size_t t = 0; t < n; ++t) {
    glm::dvec3 v0(scene.positions[3 * t]), e1 = glm::dvec3(scene.positions[3 * t + 1]) - v0,
        e2 = glm::dvec3(scene.positions[3 * t + 2]) - v0;
    glm::dvec3 p = glm::cross(d, e2);
    double det = glm::dot(e1, p);
    if (det == 0.0) continue;
    double inv = 1.0 / det;
    glm::dvec3 s = o - v0;
    double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) continue;
    glm::dvec3 q = glm::cross(s, e1);
    double v = glm::dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    double tt = glm::dot(e2, q) * inv;
    if (tt > 0.0 && tt < best) {
      best = tt;
      id = uint32_t(t + 1);
    }
  }
  if (t_hit) *t_hit = best;
  return id;
}

}  // namespace zz::test
