// The gpu tests' busy scene: a sphere, boxes (one resting on another), a floor grid, a
// wall with a picture on it: silhouettes, creases, contact edges and near-coplanar layers.
#pragma once

#include "test_scenes.h"

namespace zz::test {

inline Scene busy_scene() {
  SceneBuilder b;
  b.sphere({-0.5f, 0.0f, 0.0f}, 0.55f, 64, 32);
  b.box({0.2f, -0.5f, -0.4f}, {0.9f, 0.2f, 0.2f});
  b.box({0.25f, 0.2f, -0.3f}, {0.6f, 0.45f, 0.1f});  // resting on the first box: contact crease
  b.grid({-2.0f, -0.5f, 2.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -4.0f}, 10);
  b.quad({-1.5f, -0.5f, -1.0f}, {1.5f, -0.5f, -1.0f}, {1.5f, 1.2f, -1.0f}, {-1.5f, 1.2f, -1.0f});  // wall
  b.quad({-0.3f, 0.3f, -0.98f}, {0.3f, 0.3f, -0.98f}, {0.3f, 0.7f, -0.98f}, {-0.3f, 0.7f, -0.98f});  // picture
  return b.done();
}

// The busy scene with its floor grid in two materials, checkered by quad: coplanar
// material boundaries for the visibility map's material rule.
inline Scene busy_checker_scene() {
  Scene s = busy_scene();
  s.materials.push_back(s.materials[0]);
  // The grid's 10 x 10 quads (2 triangles each) follow the sphere and the boxes.
  const size_t grid_first = s.material_of.size() - 2 * 100 - 2 * 2;
  for (size_t q = 0; q < 100; ++q)
    s.material_of[grid_first + 2 * q] = s.material_of[grid_first + 2 * q + 1] = uint32_t((q / 10 + q % 10) % 2);
  return s;
}

inline size_t flagged(const GeoMap& m) {
  size_t n = 0;
  for (uint8_t f : m.flags) n += f != 0;
  return n;
}

}  // namespace zz::test
