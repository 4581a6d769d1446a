// Tiles of a frame (core/tile.h): the grid, a region's part of it, and the centre-out order.
#include "core/tile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <vector>

namespace zz {

// So that a failed comparison prints the rect, not its bytes.
static void PrintTo(const TileRect& r, std::ostream* os) {
  *os << "{" << r.x0 << ", " << r.y0 << ", " << r.x1 << ", " << r.y1 << "}";
}

namespace {

// centre_out: the same tiles, nearest the frame's centre first (the viewer shows the middle first).
TEST(Tiles, CentreOutStartsAtTheFramesCentreAndMovesOutwards) {
  const int w = 300, h = 100;  // not square: each axis measured from its own centre
  const std::vector<TileRect> raster = make_tiles(w, h, 32);
  const std::vector<TileRect> tiles = centre_out(raster, w, h);
  ASSERT_EQ(tiles.size(), raster.size());
  auto distance2 = [&](const TileRect& t) {
    const double dx = 0.5 * (t.x0 + t.x1) - 0.5 * w, dy = 0.5 * (t.y0 + t.y1) - 0.5 * h;
    return dx * dx + dy * dy;
  };
  for (size_t i = 1; i < tiles.size(); ++i) EXPECT_LE(distance2(tiles[i - 1]), distance2(tiles[i])) << "tile " << i;
  EXPECT_EQ(tiles.front(), (TileRect{128, 32, 160, 64}));  // holds the centre pixel (150, 50)
  for (const TileRect& t : raster) EXPECT_EQ(std::count(tiles.begin(), tiles.end(), t), 1);
}

}  // namespace
}  // namespace zz
