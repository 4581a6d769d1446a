// A region-limited visibility map has, inside the region, exactly the full map's flags
// (same tiles, projection and viewport; only the scissor changes) and zero outside.
#include <gtest/gtest.h>

#include <atomic>

#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_busy_scene.h"

namespace zz::test {
namespace {

using VisibilityRegionTest = GpuTest;

void expect_crop(const GeoMap& full, const GeoMap& part, const TileRect& r, size_t min_flags = 5) {
  ASSERT_EQ(part.width, full.width);
  ASSERT_EQ(part.height, full.height);
  size_t inside = 0, wrong = 0, outside_set = 0;
  for (int y = 0; y < full.height; ++y)
    for (int x = 0; x < full.width; ++x) {
      const bool in = x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
      if (in) {
        inside += full.at(x, y);
        wrong += full.at(x, y) != part.at(x, y);
      } else {
        outside_set += part.at(x, y);
      }
    }
  EXPECT_EQ(wrong, 0u) << "region " << r.x0 << "," << r.y0 << " - " << r.x1 << "," << r.y1;
  EXPECT_EQ(outside_set, 0u);
  EXPECT_GE(inside, min_flags) << "a region without flags proves nothing";
}

TEST_F(VisibilityRegionTest, RegionEqualsCropOfTheFullMap) {
  const Scene scene = busy_scene();
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  const TileRect regions[] = {{0, 0, 101, 67}, {13, 7, 58, 40}, {31, 21, 34, 23}, {64, 0, 101, 67}, {5, 40, 97, 66}};
  for (int ss : {4, 6}) {
    VisibilitySettings whole;
    whole.supersample = ss;
    VisibilitySettings tiles = whole;
    tiles.max_tile_dim = 12 * ss + 2;  // 12 x 12-pixel tiles: regions cross tile edges
    for (const VisibilitySettings& s : {whole, tiles}) {
      const GeoMap full = pass.run(camera, 101, 67, s);
      ASSERT_GT(flagged(full), 100u);
      for (const TileRect& r : regions) {
        VisibilityTimings t;
        const GeoMap part = pass.run(camera, 101, 67, s, &t, r);
        expect_crop(full, part, r, r.width() * r.height() < 100 ? 0 : 5);
        if (s.max_tile_dim == 0) {
          EXPECT_EQ(t.tiles, 1);
        }
      }
      // One flagged pixel alone, not the first pixel of a flag word (its x, not its index).
      size_t first = 0;
      while (first < full.flags.size() && !(full.flags[first] && first % 101 % ZZ_PIXELS_PER_WORD != 0)) ++first;
      ASSERT_LT(first, full.flags.size());
      const int x = int(first % 101), y = int(first / 101);
      expect_crop(full, pass.run(camera, 101, 67, s, nullptr, TileRect{x, y, x + 1, y + 1}), {x, y, x + 1, y + 1}, 1);
    }
  }
}

TEST_F(VisibilityRegionTest, ARegionOfAFrameTooBigForOneFlagBufferIsMade) {
  // 16384 x 8200 pixels need 134.3 M flag bytes, past lavapipe's 128 MiB storage-buffer
  // range: the whole frame is refused, but the flag buffer holds a region's rows only, so a
  // farm's region of it is made. Two overlapping regions agree where they overlap.
  const Scene scene = busy_scene();
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  VisibilitySettings s;
  s.supersample = 1;
  s.max_tile_dim = 258;  // 256-pixel tiles keep the targets small
  const int w = 16384, h = 8200;
  const TileRect a{8002, 4001, 8258, 4257}, b{8130, 4100, 8400, 4300};
  const GeoMap ma = pass.run(camera, w, h, s, nullptr, a), mb = pass.run(camera, w, h, s, nullptr, b);
  size_t flagged_a = 0, differ = 0;
  for (int y = a.y0; y < a.y1; ++y)
    for (int x = a.x0; x < a.x1; ++x) {
      flagged_a += ma.at(x, y) != 0;
      if (x >= b.x0 && y >= b.y0 && x < b.x1 && y < b.y1) differ += ma.at(x, y) != mb.at(x, y);
    }
  EXPECT_GT(flagged_a, 20u) << "a region without flags proves nothing";
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(ma.at(a.x0 - 1, a.y0), 0);  // nothing outside
  if (context().properties().limits.maxStorageBufferRange < uint64_t(w) * h) {
    EXPECT_THROW(pass.run(camera, w, h, s), Error);
    // The same refusal before any of the frame's work (render checks it as a job starts),
    // and none for the region, whose flags are its own rows.
    try {
      VisibilityPass::check_fits(context(), scene.positions.size() / 3, w, h);
      ADD_FAILURE() << "a frame of too many flags passed";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the frame's flags need a storage buffer"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(VisibilityPass::check_fits(context(), scene.positions.size() / 3, w, h, a));
  }
  // A scene of more triangles than one binding holds: refused before any upload.
  const size_t too_many = size_t(context().properties().limits.maxStorageBufferRange / 16) + 1;
  EXPECT_THROW(VisibilityPass::check_fits(context(), too_many, 64, 64), Error);
  EXPECT_NO_THROW(VisibilityPass::check_fits(context(), too_many - 1, 64, 64));
}

TEST(VisibilityFrameBytes, ARegionsFlagsAreItsOwnRowsOnly) {
  // Device-free: the flag buffer of a region is its word-aligned columns times its rows.
  VisibilitySettings s;
  s.supersample = 4;
  const uint64_t full = VisibilityPass::frame_bytes(16384, 16384, s, 1000);
  const uint64_t part = VisibilityPass::frame_bytes(16384, 16384, s, 1000, TileRect{8190, 100, 8254, 164});
  EXPECT_EQ(full - part, uint64_t(16384) / 4 * 16384 * 4 - 17 * 64 * 4);  // x 8188..8256: 17 words
}

// A frame above the band floor is planned as about eight bands, so only a band's targets
// are mapped in; a small one stays one tile; the memory cap still rules large frames.
TEST(VisibilityFrameBytes, FramesAreBandedToAboutAnEighthOfTheirSamples) {
  VisibilitySettings s;
  s.supersample = 4;
  const uint64_t flags_1024 = uint64_t(1024) / 4 * 1024 * 4;
  const uint64_t frame_1024 = uint64_t(4098) * 4098 * 8;
  const uint64_t targets = VisibilityPass::frame_bytes(1024, 1024, s, 109000) - flags_1024;
  EXPECT_LE(targets, frame_1024 / 8 + 4098 * 8 * 4);  // an eighth, to a pixel row
  EXPECT_GE(targets, frame_1024 / 10);
  const uint64_t flags_200 = uint64_t(200) / 4 * 200 * 4;
  EXPECT_EQ(VisibilityPass::frame_bytes(200, 200, s, 1000) - flags_200, uint64_t(802) * 802 * 8);  // under the floor: whole
  // A scene of 2 M triangles: a band's vertex pass would cost more than its first touch
  // saves, so the frame stays whole (it fits the memory cap).
  EXPECT_EQ(VisibilityPass::frame_bytes(1024, 1024, s, 2000000) - flags_1024, frame_1024);
  EXPECT_EQ(VisibilityPass::band_floor(s, 1000), s.min_band_samples);
  EXPECT_EQ(VisibilityPass::band_floor(s, 2000000), 32000000);
  s.min_band_samples = int64_t(1) << 40;  // no banding: the frame whole, within the cap
  EXPECT_EQ(VisibilityPass::frame_bytes(1024, 1024, s, 1000) - flags_1024, frame_1024);
  EXPECT_LE(VisibilityPass::frame_bytes(16384, 16384, s, 1000), uint64_t(s.max_tile_samples) * 8 + uint64_t(16384) * 16384);
}

// The tile plan keeps a tile's id image (samples plus the one-sample ring) within the
// largest image side it is given (max_tile_dim, else the device's) and within the sample
// budget (max_tile_samples). Widths here are multiples of 4 pixels, so the target is not
// padded. Mutation testing: the ring left out of either bound ((max_dim - 2) / s,
// (max_rows - 2) / s) changed no test; such a target is past the device's image limit.
TEST(VisibilityFrameBytes, TheTilePlanKeepsTheTargetWithinTheImageLimitAndTheBudget) {
  for (int s : {1, 3, 4, 6}) {
    VisibilitySettings settings;
    settings.supersample = s;
    const uint64_t flags = uint64_t(1000) / 4 * 1000 * 4;
    for (int dim = 6 * s + 2; dim < 6 * s + 2 + 4 * s; ++dim) {  // every remainder of (dim - 2) / s
      settings.max_tile_dim = dim;
      EXPECT_LE(VisibilityPass::frame_bytes(1000, 1000, settings, 1000) - flags, uint64_t(dim) * dim * 8)
          << "S " << s << ", images up to " << dim;
    }
    settings.max_tile_dim = 0;
    const int64_t row = 1000 * s + 2;
    for (int64_t rows = 2 * s + 2; rows < 2 * s + 2 + 2 * s; ++rows) {  // every remainder of (rows - 2) / s
      settings.max_tile_samples = row * rows;
      EXPECT_LE(VisibilityPass::frame_bytes(1000, 1000, settings, 1000) - flags, uint64_t(row * rows) * 8)
          << "S " << s << ", " << rows << " rows";
    }
  }
}

// A cancelled map (the viewer's camera moved on) stops at its next band with an empty map;
// an uncancelled one is the map itself.
TEST_F(VisibilityRegionTest, ACancelledMapStopsEmpty) {
  const Scene scene = busy_scene();
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  std::atomic<bool> cancel{true};
  EXPECT_TRUE(pass.run(camera, 64, 48, {}, nullptr, std::nullopt, &cancel).empty());
  cancel = false;
  EXPECT_EQ(pass.run(camera, 64, 48, {}, nullptr, std::nullopt, &cancel).flags, pass.run(camera, 64, 48, {}).flags);
}

TEST_F(VisibilityRegionTest, RegionIsClampedAndAnEmptyOneIsAnError) {
  const Scene scene = busy_scene();
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  const GeoMap full = pass.run(camera, 64, 48, {});
  expect_crop(full, pass.run(camera, 64, 48, {}, nullptr, TileRect{-10, -10, 30, 20}), {0, 0, 30, 20});
  EXPECT_THROW(pass.run(camera, 64, 48, {}, nullptr, TileRect{70, 0, 80, 10}), Error);
}

}  // namespace
}  // namespace zz::test
