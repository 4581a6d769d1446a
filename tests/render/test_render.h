// A whole-frame render of a scene built in code, for the render and robustness tests.
#pragma once

#include <gtest/gtest.h>

#include <cstring>

#include "accel/bvh.h"
#include "core/geo_map.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace zz::test {

// Renders cameras[0] of `scene` with an empty visibility map.
inline Film render(const Scene& scene, const RenderSettings& settings, RenderStats* stats_out = nullptr,
                   const RenderCallbacks& callbacks = {}) {
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  Film film;
  RenderStats stats;
  render_frame(shader, scene.cameras[0], GeoMap{}, settings, film, stats, callbacks);
  // The shader sets a NaN sample to black and counts it: the film alone cannot show one.
  EXPECT_EQ(stats.rays.nan_radiance, 0u) << scene.name << ": the shader made NaN radiance";
  EXPECT_EQ(stats.rays.capped_radiance, 0u) << scene.name << ": radiance above the shader's cap";
  if (stats_out) *stats_out = stats;
  return film;
}

// The same image to the bit, and the same rays and levels per pixel: what determinism
// across threads, tiles and orders promises.
inline bool bit_identical(const Film& a, const Film& b) {
  return a.width == b.width && a.height == b.height && a.radiance.size() == b.radiance.size() &&
         std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec3)) == 0 &&
         a.rays == b.rays && a.level == b.level;
}

}  // namespace zz::test
