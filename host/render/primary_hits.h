// The data of the depth, normal and albedo AOVs: per pixel, what the camera ray through
// the pixel's centre (x + 1/2, y + 1/2) hits first (Shader::primary4).
//
// Why the centre ray and not one of the colour's samples: the adaptive sampler's level-1
// rays go through pixel corners, each shared by four pixels, and its later rays exist only
// where it refines, so no sample belongs to every pixel; the centre ray is the same
// definition for every AA mode, tiling and thread count, and is traced only when one of
// these AOVs is asked for (the colour path never sees it). It is one extra ray per pixel
// (plus cut-out continuations), not counted in the render's ray statistics.
//   depth   distance from the camera position to the hit along the ray (not view-space z);
//           +inf where the ray misses everything
//   normal  world-space shading normal (normal map applied) turned towards the camera,
//           unit length; (0, 0, 0) on a miss
//   albedo  linear base colour (glTF baseColorFactor x baseColorTexture); (0, 0, 0) on a miss
#pragma once

#include <glm/glm.hpp>

#include <atomic>
#include <vector>

#include "core/tile.h"
#include "render/ray_counters.h"
#include "render/shader.h"
#include "scene/camera.h"

namespace zz {

struct PrimaryHits {
  int width = 0, height = 0;  // the region traced, row-major from its top-left pixel
  std::vector<float> depth;
  std::vector<glm::vec3> normal;
  std::vector<glm::vec3> albedo;
};

// The centre rays of `region`'s pixels in a width x height frame, rows in parallel on
// `threads` threads (0 = all cores). With `cancel` set by another thread it stops early
// (the caller discards the result). `rays` receives the rays traced.
PrimaryHits trace_primary_hits(const Shader& shader, const Camera& camera, int width, int height,
                               const TileRect& region, int threads, const std::atomic<bool>* cancel = nullptr,
                               RayCounters* rays = nullptr);

}  // namespace zz
