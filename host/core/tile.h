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
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  bool operator==(const TileRect&) const = default;
};

// The overlap of two rects (empty if they do not overlap).
TileRect intersect(const TileRect& a, const TileRect& b);

struct TileTarget {
  TileRect rect;
  int frame_width = 0;  // the whole frame: samplers clip margins and the corner ring to it
  int frame_height = 0;
  glm::vec3* radiance = nullptr;  // the film's buffers, indexed by index(x, y)
  uint8_t* rays = nullptr;        // rays traced for the pixel (saturates at 255); may be null
  uint8_t* level = nullptr;       // AA level reached (1..3) + 4 * vertical; may be null
  // The pixels the buffers hold, in frame coordinates: the whole frame, or the region
  // being rendered (`zigzag render --region`). Always contains `rect`.
  TileRect buffer;

  size_t index(int x, int y) const { return size_t(y - buffer.y0) * size_t(buffer.width()) + size_t(x - buffer.x0); }
  glm::vec3& pixel(int x, int y) const { return radiance[index(x, y)]; }
};

// The tiles of a frame in raster order (the last row/column may be partial).
std::vector<TileRect> make_tiles(int width, int height, int tile_size = kTileSize);

// The frame's tiles clipped to `region` (tiles outside it dropped): a region render uses
// the same grid, aligned to the frame origin, as the full frame.
std::vector<TileRect> make_tiles(int width, int height, const TileRect& region, int tile_size = kTileSize);

// The same tiles ordered by distance of their centre from the frame centre (the viewer
// shows the middle first). Results never depend on the order.
std::vector<TileRect> centre_out(std::vector<TileRect> tiles, int width, int height);

}  // namespace zz
