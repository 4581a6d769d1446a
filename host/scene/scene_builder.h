// Scenes built in code: triangles, quads, watertight UV spheres, boxes and grids with one
// default material and camera. Used by tests and benchmarks that need geometry without a
// file; flat per-triangle normals (0,0,1 for a degenerate triangle).
#pragma once

#include <glm/glm.hpp>

#include <cmath>

#include "scene/scene.h"

namespace zz {

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

}  // namespace zz
