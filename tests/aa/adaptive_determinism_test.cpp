// The image does not depend on tile size, thread count or tile order (ALGORITHM.md §1).
#include <gtest/gtest.h>

#include <cstring>

#include "aa/analytic.h"
#include "test_sources.h"

namespace zz {
namespace {

bool same(const Film& a, const Film& b) {
  return a.radiance.size() == b.radiance.size() &&
         std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec3)) == 0 &&
         a.rays == b.rays && a.level == b.level;
}

TEST(AdaptiveDeterminism, BitIdenticalAcrossTilesAndThreads) {
  const AnalyticImage star = make_analytic_image("star", 90);
  const GeoMap geo = analytic_geo_map(star, 4);
  for (Filter f : {Filter::Box, Filter::Mitchell})
    for (GeoPolicy gp : {GeoPolicy::Paper, GeoPolicy::Split, GeoPolicy::All})
      for (unsigned sig : {kSignatureNone, kSignatureObject}) {  // signatures: corners carry one more array
        AdaptiveSettings s;
        s.filter = f;
        s.geo_policy = gp;
        s.signature = sig;
        s.tables = find_table_set("tuned");
        const AnalyticSource source{&star, sig};
        const Film ref = test::render(source, 90, 90, s, 64, 1, geo);
        // Level 1 traced once for the frame (the corner field) or per tile (the viewer's path,
        // and frames whose field is over budget): the same image.
        for (bool field : {true, false})
          for (int tile : {64, 13, 1, 90, 7})
            for (int threads : {1, 2}) {
              SCOPED_TRACE(testing::Message() << to_string(f) << " " << to_string(gp) << " signature "
                                              << signature_name(sig) << " tile " << tile << " threads " << threads
                                              << (field ? " corner field" : " per-tile corners"));
              EXPECT_TRUE(same(ref, test::render(source, 90, 90, s, tile, threads, geo, nullptr, field)));
            }
      }
}

TEST(AdaptiveDeterminism, TileOrderDoesNotMatter) {
  // Render tiles by hand in reverse order into one frame.
  const AnalyticImage zp = make_analytic_image("zoneplate", 70);
  AdaptiveSettings s;
  s.filter = Filter::Mitchell;
  const Film ref = test::render(AnalyticSource{&zp}, 70, 70, s, 16);
  Film fb(70, 70);
  std::vector<TileRect> tiles = make_tiles(70, 70, 16);
  AaStats st;
  for (auto it = tiles.rbegin(); it != tiles.rend(); ++it) {
    const TileTarget t = fb.target(*it);
    AnalyticSource src{&zp};
    render_tile_adaptive(src, t, GeoMap{}, s, st);
  }
  EXPECT_TRUE(same(ref, fb));
}

// AaStats count a tile's own pixels once, whatever the tiling; the Mitchell margin's extra
// refinement rays (E..H and zones, rays - 1 per margin pixel) are reported in margin_rays.
TEST(AdaptiveDeterminism, OwnPixelCountsDoNotDependOnTheTilingAndTheMarginRaysAreTheDifference) {
  const AnalyticImage star = make_analytic_image("star", 48);
  AdaptiveSettings s;
  s.filter = Filter::Mitchell;
  s.tables = find_table_set("tuned");
  const AnalyticSource source{&star};
  AaStats whole, tiled;
  test::render(source, 48, 48, s, 48, 1, {}, &whole);  // one tile: no margin inside the frame
  test::render(source, 48, 48, s, 7, 1, {}, &tiled);
  ASSERT_GT(whole.level2_pixels, 0u);
  EXPECT_EQ(whole.margin_rays, 0u);
  EXPECT_EQ(tiled.pixels, 48u * 48u);
  EXPECT_EQ(tiled.pixels, whole.pixels);
  EXPECT_EQ(tiled.level2_pixels, whole.level2_pixels);
  EXPECT_EQ(tiled.level3_pixels, whole.level3_pixels);
  EXPECT_EQ(tiled.vertical_pixels, whole.vertical_pixels);
  EXPECT_EQ(tiled.zones_traced, whole.zones_traced);
  EXPECT_EQ(tiled.zones_interpolated, whole.zones_interpolated);
  // Every refined pixel traces or interpolates each of its five zones.
  EXPECT_EQ(whole.zones_traced + whole.zones_interpolated, 5 * whole.level2_pixels);
  // The corner field traces level 1 once for the frame: the tiling adds only margin refinement.
  EXPECT_EQ(tiled.rays[0], whole.rays[0]);
  EXPECT_GT(tiled.margin_rays, 0u);
  EXPECT_EQ(tiled.rays[1] + tiled.rays[2] - tiled.margin_rays, whole.rays[1] + whole.rays[2]);
}

}  // namespace
}  // namespace zz
