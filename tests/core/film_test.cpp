// The film (core/film.h): the whole frame or a region of it, and the tile targets into it.
#include "core/film.h"

#include <gtest/gtest.h>

namespace zz {
namespace {

// A region's film holds only the region and indexes its buffers from the region's corner.
TEST(Film, ARegionsTargetIndexesItsBuffersFromTheRegionsCorner) {
  Film film(100, 80, TileRect{10, 20, 40, 60});
  EXPECT_EQ(film.width, 30);
  EXPECT_EQ(film.height, 40);
  EXPECT_EQ(film.radiance.size(), 1200u);
  EXPECT_EQ(film.rays.size(), 1200u);
  EXPECT_EQ(film.level.size(), 1200u);
  EXPECT_EQ(film.window(), (TileRect{10, 20, 40, 60}));
  const TileTarget t = film.target({16, 24, 32, 40});
  EXPECT_EQ(t.frame_width, 100);
  EXPECT_EQ(t.frame_height, 80);
  EXPECT_EQ(t.index(10, 20), 0u);     // the region's first pixel
  EXPECT_EQ(t.index(39, 59), 1199u);  // and its last
  t.pixel(17, 25) = glm::vec3(1.0f, 2.0f, 3.0f);
  t.rays[t.index(17, 25)] = 9;
  t.level[t.index(17, 25)] = 3;
  const size_t i = size_t(25 - 20) * 30 + size_t(17 - 10);
  EXPECT_EQ(film.radiance[i], glm::vec3(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(film.rays[i], 9);
  EXPECT_EQ(film.level[i], 3);
}

// is_region: every film but one holding the whole frame is a region, whichever side it lacks.
TEST(Film, OnlyTheWholeFrameIsNotARegion) {
  EXPECT_FALSE(Film(64, 48).is_region());
  EXPECT_FALSE(Film(64, 48, TileRect{0, 0, 64, 48}).is_region());
  EXPECT_TRUE(Film(64, 48, TileRect{0, 0, 32, 48}).is_region());  // the left half
  EXPECT_TRUE(Film(64, 48, TileRect{0, 0, 64, 24}).is_region());  // the top half
  EXPECT_TRUE(Film(64, 48, TileRect{32, 0, 64, 48}).is_region());
  EXPECT_TRUE(Film(64, 48, TileRect{0, 24, 64, 48}).is_region());
}

}  // namespace
}  // namespace zz
