// The frame being rendered: linear HDR radiance plus per-pixel AOVs. Samplers write
// into it through TileTargets (disjoint tiles, so workers never share a pixel).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "core/tile.h"

namespace zz {

struct Film {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> radiance;  // linear RGB
  std::vector<uint8_t> rays;        // rays traced per pixel (saturating)
  std::vector<uint8_t> level;       // AA level reached (1..3), +4 when oriented vertically

  Film() = default;
  Film(int w, int h)
      : width(w), height(h), radiance(size_t(w) * h), rays(size_t(w) * h), level(size_t(w) * h) {}

  TileTarget target(const TileRect& rect) {
    TileTarget t;
    t.rect = rect;
    t.frame_width = width;
    t.frame_height = height;
    t.radiance = radiance.data();
    t.rays = rays.data();
    t.level = level.data();
    return t;
  }
};

}  // namespace zz
