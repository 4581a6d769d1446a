// The frame being rendered: linear HDR radiance plus per-pixel AOVs. Samplers write
// into it through TileTargets (disjoint tiles, so workers never share a pixel).
//
// A film holds either the whole frame or one region of it (`zigzag render --region`):
// `width` x `height` is what the buffers hold (OpenEXR's data window), at `x0, y0` in a
// frame of `frame_width` x `frame_height` (the display window).
//
// `channels` are extra named float planes over the data window: the AOVs an EXR holds
// as layers of its own (`zigzag render -o x.exr --aov depth`, render/aov_layers.h).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "core/tile.h"

namespace zz {

// One extra channel: its EXR name ("depth", "normal.X", ...) and width * height values.
struct FilmChannel {
  std::string name;
  std::vector<float> values;
};

struct Film {
  int width = 0;   // buffer size: the data window
  int height = 0;
  int x0 = 0, y0 = 0;                     // data window origin in the frame
  int frame_width = 0, frame_height = 0;  // the display window
  std::vector<glm::vec3> radiance;  // linear RGB
  std::vector<uint8_t> rays;        // rays traced per pixel (saturating)
  std::vector<uint8_t> level;       // AA level reached (1..3), +4 when oriented vertically
  std::vector<FilmChannel> channels;  // extra layers for an EXR; empty unless AOVs asked for them

  Film() = default;
  Film(int w, int h) : Film(w, h, TileRect{0, 0, w, h}) {}
  Film(int frame_w, int frame_h, const TileRect& window)
      : width(window.width()), height(window.height()), x0(window.x0), y0(window.y0), frame_width(frame_w),
        frame_height(frame_h), radiance(size_t(width) * height), rays(size_t(width) * height),
        level(size_t(width) * height) {}

  TileRect window() const { return {x0, y0, x0 + width, y0 + height}; }
  bool is_region() const { return x0 != 0 || y0 != 0 || width != frame_width || height != frame_height; }

  TileTarget target(const TileRect& rect) {
    TileTarget t;
    t.rect = rect;
    t.frame_width = frame_width;
    t.frame_height = frame_height;
    t.radiance = radiance.data();
    t.rays = rays.data();
    t.level = level.data();
    t.buffer = window();
    return t;
  }
};

}  // namespace zz
