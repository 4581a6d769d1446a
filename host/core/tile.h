// What a sampler writes for one tile: radiance and per-pixel AOVs, as views into the
// frame's buffers (no copies; tiles never overlap, so workers never share a pixel).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace zz {

inline constexpr int kTileSize = 64;  // ALGORITHM.md §1

struct TileRect {
  int x0 = 0, y0 = 0;  // first pixel
  int x1 = 0, y1 = 0;  // one past the last pixel
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

struct TileTarget {
  TileRect rect;
  int frame_width = 0;  // row stride of every buffer below, in pixels
  int frame_height = 0;
  glm::vec3* radiance = nullptr;  // frame buffer, indexed [y * frame_width + x]
  uint8_t* rays = nullptr;        // rays traced for the pixel (saturates at 255); may be null
  uint8_t* level = nullptr;       // AA level reached (1..3) + 4 * vertical; may be null

  glm::vec3& pixel(int x, int y) const { return radiance[size_t(y) * frame_width + x]; }
};

// The tiles of a frame in raster order (the last row/column may be partial).
std::vector<TileRect> make_tiles(int width, int height, int tile_size = kTileSize);

// The same tiles ordered by distance of their centre from the frame centre (the viewer
// shows the middle first). Results never depend on the order.
std::vector<TileRect> centre_out(std::vector<TileRect> tiles, int width, int height);

}  // namespace zz
