#include "viewer/display_frame.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "render/aov.h"
#include "render/image_io.h"

namespace zz {
namespace {

Film gradient_film(int w, int h) {
  Film film(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      // HDR values spanning dark to over-bright, plus the NaN/negative cases the tone map clamps.
      film.radiance[i] = glm::vec3(0.013f * x, 0.021f * y, std::fmod(0.37f * float(i), 5.0f));
      film.rays[i] = uint8_t(1 + (x + y) % 25);
      film.level[i] = uint8_t((x % 3) + 1 + (y % 2) * 4);
    }
  film.radiance[0] = glm::vec3(-1.0f, NAN, INFINITY);
  return film;
}

TEST(DisplayFrame, TilesGiveExactlyTheDisplayBytesOfRender) {
  const Film film = gradient_film(150, 70);  // partial tiles on both axes
  ToneMap tonemap;
  tonemap.exposure = 1.7f;
  DisplayFrame frame;
  frame.resize(film.width, film.height);
  for (const TileRect& t : centre_out(make_tiles(film.width, film.height), film.width, film.height))
    frame.put_tile(film, t, 1, tonemap);
  EXPECT_EQ(frame.rgb(ViewMode::Image), display_bytes(film, tonemap));
}

TEST(DisplayFrame, PreviewTilesAreUpscaledNearest) {
  const Film coarse = gradient_film(5, 3);
  DisplayFrame frame;
  frame.resize(18, 10);  // not a multiple of 4: the last blocks are clipped
  frame.put_tile(coarse, {0, 0, 5, 3}, 4, ToneMap{});
  const std::vector<uint8_t> big = frame.rgb(ViewMode::Image);
  const std::vector<uint8_t> small = display_bytes(coarse, ToneMap{});
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 18; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(big[(size_t(y) * 18 + x) * 3 + c], small[(size_t(y / 4) * 5 + x / 4) * 3 + c]) << x << "," << y;
}

TEST(DisplayFrame, ComposeSwizzlesForBgraAndSetsAlpha) {
  const Film film = gradient_film(8, 4);
  DisplayFrame frame;
  frame.resize(8, 4);
  frame.put_tile(film, {0, 0, 8, 4}, 1, ToneMap{});
  const std::vector<uint8_t> rgb = frame.rgb(ViewMode::Image);
  std::vector<uint8_t> bgra, rgba;
  int w = 0, h = 0;
  frame.compose(ViewMode::Image, true, bgra, w, h);
  EXPECT_EQ(w, 8);
  EXPECT_EQ(h, 4);
  frame.compose(ViewMode::Image, false, rgba, w, h);
  for (size_t i = 0; i < 32; ++i) {
    EXPECT_EQ(bgra[i * 4 + 0], rgb[i * 3 + 2]);
    EXPECT_EQ(bgra[i * 4 + 1], rgb[i * 3 + 1]);
    EXPECT_EQ(bgra[i * 4 + 2], rgb[i * 3 + 0]);
    EXPECT_EQ(bgra[i * 4 + 3], 255);
    EXPECT_EQ(rgba[i * 4 + 0], rgb[i * 3 + 0]);
    EXPECT_EQ(rgba[i * 4 + 2], rgb[i * 3 + 2]);
  }
}

TEST(DisplayFrame, AovViewsUseTheRenderAovColours) {
  const Film film = gradient_film(16, 8);
  DisplayFrame frame;
  frame.resize(16, 8);
  frame.put_tile(film, {0, 0, 16, 8}, 1, ToneMap{});
  const std::vector<uint8_t> rays = frame.rgb(ViewMode::Rays);
  const std::vector<uint8_t> level = frame.rgb(ViewMode::Level);
  for (size_t i = 0; i < 128; ++i) {
    uint8_t want[3];
    ray_count_colour(film.rays[i], want);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(rays[i * 3 + c], want[c]);
  }
  // Levels 1, 2, 3 and their vertical variants are six different colours.
  std::vector<std::array<uint8_t, 3>> seen;
  for (int l : {1, 2, 3, 5, 6, 7}) {
    uint8_t c[3];
    level_colour(l, c);
    seen.push_back({c[0], c[1], c[2]});
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(std::unique(seen.begin(), seen.end()) - seen.begin(), 5);  // level 1 has no orientation
  uint8_t c[3];
  level_colour(film.level[1], c);
  EXPECT_EQ(level[3 + 0], c[0]);
  EXPECT_EQ(level[3 + 2], c[2]);
}

TEST(DisplayFrame, GeoViewShowsFlagsOrNotAvailable) {
  DisplayFrame frame;
  frame.resize(4, 2);
  EXPECT_FALSE(frame.has_geo());
  GeoMap geo{4, 2, {0, 1, 0, 0, 1, 1, 0, 0}};
  frame.set_geo(geo);
  EXPECT_TRUE(frame.has_geo());
  const std::vector<uint8_t> rgb = frame.rgb(ViewMode::Geo);
  for (size_t i = 0; i < 8; ++i) EXPECT_EQ(rgb[i * 3], geo.flags[i] ? 255 : 0);
  frame.resize(5, 2);  // a new size drops the stale map
  EXPECT_FALSE(frame.has_geo());
}

TEST(DisplayFrame, VersionMovesOnEveryChange) {
  DisplayFrame frame;
  const uint64_t v0 = frame.version();
  frame.resize(64, 64);
  const uint64_t v1 = frame.version();
  EXPECT_GT(v1, v0);
  frame.resize(64, 64);  // same size: no change
  EXPECT_EQ(frame.version(), v1);
  Film film(64, 64);
  frame.put_tile(film, {0, 0, 8, 8}, 1, ToneMap{});
  EXPECT_GT(frame.version(), v1);
}

// A visibility map of another size than the frame (made before a resize) is not shown:
// the geo view is the "not available" checkerboard, and no flag past the map is read.
TEST(DisplayFrame, AMapOfAnotherSizeIsNotShown) {
  DisplayFrame frame;
  frame.resize(4, 2);
  frame.set_geo(GeoMap{2, 2, {1, 1, 1, 1}});
  EXPECT_FALSE(frame.has_geo());
  const std::vector<uint8_t> rgb = frame.rgb(ViewMode::Geo);
  for (size_t i = 0; i < 8; ++i) EXPECT_EQ(rgb[i * 3], 32) << i;  // the checkerboard's first square
}

// In the rays view a pixel not rendered yet (0 rays) is black, not the ramp's 1-ray colour.
TEST(DisplayFrame, PixelsNotRenderedYetAreBlackInTheRaysView) {
  DisplayFrame frame;
  frame.resize(3, 2);
  for (const uint8_t v : frame.rgb(ViewMode::Rays)) EXPECT_EQ(v, 0);
  uint8_t one[3];
  heat_color(1, one);
  EXPECT_GT(one[0] + one[1] + one[2], 0);
}

}  // namespace
}  // namespace zz
