#include "core/tile.h"

#include <algorithm>

namespace zz {

std::vector<TileRect> make_tiles(int width, int height, int tile_size) {
  std::vector<TileRect> tiles;
  for (int y = 0; y < height; y += tile_size)
    for (int x = 0; x < width; x += tile_size)
      tiles.push_back({x, y, std::min(x + tile_size, width), std::min(y + tile_size, height)});
  return tiles;
}

TileRect intersect(const TileRect& a, const TileRect& b) {
  TileRect r{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
  if (r.empty()) return {};
  return r;
}

std::vector<TileRect> make_tiles(int width, int height, const TileRect& region, int tile_size) {
  std::vector<TileRect> tiles;
  for (const TileRect& t : make_tiles(width, height, tile_size))
    if (const TileRect r = intersect(t, region); !r.empty()) tiles.push_back(r);
  return tiles;
}

std::vector<TileRect> centre_out(std::vector<TileRect> tiles, int width, int height) {
  auto key = [&](const TileRect& t) {
    const long dx = long(t.x0 + t.x1) - width, dy = long(t.y0 + t.y1) - height;
    return dx * dx + dy * dy;
  };
  std::stable_sort(tiles.begin(), tiles.end(), [&](const TileRect& a, const TileRect& b) { return key(a) < key(b); });
  return tiles;
}

}  // namespace zz
