#include "aa/adaptive_frame.h"

#include <algorithm>

namespace zz {

std::vector<TileRect> make_tiles(int width, int height, int tile_size) {
  std::vector<TileRect> tiles;
  for (int y = 0; y < height; y += tile_size)
    for (int x = 0; x < width; x += tile_size)
      tiles.push_back({x, y, std::min(width, x + tile_size), std::min(height, y + tile_size)});
  return tiles;
}

}  // namespace zz
