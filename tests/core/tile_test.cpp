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

// make_tiles: tile_size squares from the frame's origin in raster order, the last column and row clipped.
TEST(Tiles, RasterOrderWithTheLastColumnAndRowClippedToTheFrame) {
  const std::vector<TileRect> want = {{0, 0, 32, 32},  {32, 0, 64, 32},  {64, 0, 70, 32},
                                      {0, 32, 32, 40}, {32, 32, 64, 40}, {64, 32, 70, 40}};
  EXPECT_EQ(make_tiles(70, 40, 32), want);
}

// intersect: the overlap of two rects, or an empty rect where they do not overlap.
TEST(Tiles, IntersectIsTheOverlapOrEmpty) {
  EXPECT_EQ(intersect({0, 0, 10, 10}, {5, 3, 20, 8}), (TileRect{5, 3, 10, 8}));
  EXPECT_EQ(intersect({5, 3, 20, 8}, {0, 0, 10, 10}), (TileRect{5, 3, 10, 8}));
  EXPECT_TRUE(intersect({0, 0, 10, 10}, {10, 0, 20, 10}).empty());  // touching is no overlap
  EXPECT_TRUE(intersect({0, 0, 10, 10}, {20, 20, 30, 30}).empty());
}

// make_tiles(region): the frame's own grid clipped to the region; tiles outside it are dropped, none is empty.
TEST(Tiles, ARegionGetsTheFramesGridClippedToItAndNoEmptyTiles) {
  const std::vector<TileRect> want = {{40, 10, 64, 30}, {64, 10, 96, 30}, {96, 10, 100, 30}};
  EXPECT_EQ(make_tiles(200, 100, TileRect{40, 10, 100, 30}, 32), want);
  // A region across a grid line splits there, as the full frame's tiles do.
  const std::vector<TileRect> across = {{60, 30, 64, 32}, {64, 30, 70, 32}, {60, 32, 64, 34}, {64, 32, 70, 34}};
  EXPECT_EQ(make_tiles(200, 100, TileRect{60, 30, 70, 34}, 32), across);
}

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
