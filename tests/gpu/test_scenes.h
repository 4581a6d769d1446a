// Scenes built in code for the gpu tests, and a brute-force first-hit reference.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "scene/scene.h"

namespace zz::test {

struct SceneBuilder {
  Scene scene;
  SceneBuilder() {
    scene.materials.push_back(Material{});
    Camera c;
    scene.cameras.push_back(c);
  }
  void tri(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    scene.positions.insert(scene.positions.end(), {a, b, c});
    glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    if (!std::isfinite(n.x)) n = glm::vec3(0.0f, 0.0f, 1.0f);
    scene.normals.insert(scene.normals.end(), {n, n, n});
    scene.uvs.insert(scene.uvs.end(), 3, glm::vec2(0.0f));
    scene.material_of.push_back(0);
  }
  void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {  // a b c d in order
    tri(a, b, c);
    tri(a, c, d);
  }
  // A UV sphere whose shared vertices are bit-identical in every triangle (watertight).
  void sphere(glm::vec3 center, float radius, int slices, int stacks) {
    auto at = [&](int i, int j) {
      if (j == 0) return center + glm::vec3(0.0f, radius, 0.0f);
      if (j == stacks) return center - glm::vec3(0.0f, radius, 0.0f);
      double th = M_PI * j / stacks, ph = 2.0 * M_PI * (i % slices) / slices;
      return center + radius * glm::vec3(glm::dvec3(std::sin(th) * std::cos(ph), std::cos(th),
                                                    std::sin(th) * std::sin(ph)));
    };
    for (int j = 0; j < stacks; ++j)
      for (int i = 0; i < slices; ++i) {
        if (j != 0) tri(at(i, j), at(i + 1, j), at(i + 1, j + 1));
        if (j != stacks - 1) tri(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      }
  }
  void box(glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 c[8];
    for (int i = 0; i < 8; ++i)
      c[i] = glm::vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& q : quads) quad(c[q[0]], c[q[1]], c[q[2]], c[q[3]]);
  }
  // An n x n grid of quads spanning corner + [0,1] u + [0,1] v; diagonals alternate.
  void grid(glm::vec3 corner, glm::vec3 u, glm::vec3 v, int n) {
    auto p = [&](int i, int j) { return corner + u * (float(i) / n) + v * (float(j) / n); };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if ((i + j) % 2) quad(p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
        else {
          tri(p(i, j), p(i + 1, j), p(i, j + 1));
          tri(p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
        }
      }
  }
  Scene done() {
    scene.finalize_materials();
    return scene;
  }
};

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
