// Zones between samples that saw different things (split_zones and GeoPolicy::Split in
// aa/adaptive_pixel.h).
#include <gtest/gtest.h>

#include <vector>

#include "test_sources.h"

namespace zz {
namespace {

// A level-2 pixel whose canonical sample `other` (A B C D E F G H = 0..7) saw something
// else than the seven others.
Level2 level2_with_other(int other) {
  alignas(16) int32_t s[8];
  for (int i = 0; i < 8; ++i) s[i] = i == other ? make_signature(7u, 0, 0) : make_signature(3u, 0, 0);
  Level2 l2{};
  l2.corner_sig = int4(s[0], s[1], s[2], s[3]);
  l2.efgh_sig = int4(s[4], s[5], s[6], s[7]);
  return l2;
}

TEST(SplitZones, ASampleThatSawSomethingElseSplitsTheZonesInterpolatedFromIt) {
  // §6: z0 from A, C, E; z1 E–G; z2 G–F; z3 F–H; z4 from H, B, D.
  const int want[8] = {/*A*/ 0b00001, /*B*/ 0b10000, /*C*/ 0b00001, /*D*/ 0b10000,
                       /*E*/ 0b00011, /*F*/ 0b01100, /*G*/ 0b00110, /*H*/ 0b11000};
  for (int s = 0; s < 8; ++s) {
    SCOPED_TRACE(s);
    EXPECT_EQ(split_zones(level2_with_other(s)), want[s]);
  }
  EXPECT_EQ(split_zones(level2_with_other(-1)), 0);  // all eight saw the same
  // A shadow from one light more is something else too (signature.h's light bits).
  Level2 l2 = level2_with_other(-1);
  l2.efgh_sig = int4(make_signature(3u, 0, 1u), make_signature(3u, 0, 0), make_signature(3u, 0, 0),
                     make_signature(3u, 0, 0));
  EXPECT_EQ(split_zones(l2), want[4]);
}

TEST(SplitZones, OnlyGeoPixelsUnderTheSplitPolicyTraceThem) {
  const TableSet& t = *find_table_set("tuned");
  const int split = 0b01100;
  // b = c0 = c1 = 0 would make a geo pixel trace every zone: a mask that fired, with the
  // tables' own zones, so that what split adds shows.
  const int tables = t.zones(1, 0, 0);
  ASSERT_NE(tables | split, tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/true, GeoPolicy::Split, false), tables | split);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/false, GeoPolicy::Split, false), tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/true, GeoPolicy::Paper, false), tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/true, GeoPolicy::All, false), kAllZones);
}

// --split-unflagged: a refined pixel the map does not flag traces its split zones too; a
// geo pixel still follows its policy.
TEST(SplitZones, UnflaggedPixelsTraceThemWhenAsked) {
  const TableSet& t = *find_table_set("tuned");
  const int split = 0b01100, tables = t.zones(1, 0, 0);
  ASSERT_NE(tables | split, tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/false, GeoPolicy::Paper, false, 0, true), tables | split);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/false, GeoPolicy::Split, false, 0, false), tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/true, GeoPolicy::Paper, false, 0, true), tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, split, /*geo=*/true, GeoPolicy::Split, false, 0, true), tables | split);
  EXPECT_TRUE(splits_zones(false, GeoPolicy::Paper, true));
  EXPECT_FALSE(splits_zones(false, GeoPolicy::Split, false));
  EXPECT_FALSE(splits_zones(true, GeoPolicy::All, true));  // All traces every zone anyway
}

// The zones of a hidden-detail flag's lattice points (zones_of_points): every point names
// every zone; each zone's four points name it alone, in either frame; A and E..H name none.
TEST(HiddenZones, LatticePointsNameTheZonesThatHoldThem) {
  for (Orientation o : {Orientation::Horizontal, Orientation::Vertical}) {
    SCOPED_TRACE(int(o));
    EXPECT_EQ(zones_of_points(o, kAllLatticePoints), kAllZones);
    EXPECT_EQ(zones_of_points(o, kAllLatticePoints | kHiddenFlag), kAllZones);
    EXPECT_EQ(zones_of_points(o, 0), 0);
    for (int z = 0; z < kZones; ++z)
      for (int lane = 0; lane < 4; ++lane) {
        const int p = physical_k(o, zone_k(z, lane));
        EXPECT_EQ(zones_of_points(o, 1u << p), 1 << z) << "zone " << z << " lane " << lane;
      }
    uint32_t traced_anyway = 1u;  // corner A
    for (int k : kLevel2K) traced_anyway |= 1u << physical_k(o, k);
    EXPECT_EQ(zones_of_points(o, traced_anyway), 0);
  }
  // Physical point 1 (u 0.04, v 0.28) is in zone 0 of the horizontal frame (strips along u)
  // and, at canonical 18, in zone 3 of the vertical one.
  EXPECT_EQ(zones_of_points(Orientation::Horizontal, 1u << 1), 0b00001);
  EXPECT_EQ(zones_of_points(Orientation::Vertical, 1u << 1), 0b01000);
}

// The map's zones (GeoMap::zones, --geo-zones): added in geo pixels; where no mask fired
// they replace §5's every zone; elsewhere, under refine_all and under GeoPolicy::All they
// change nothing.
TEST(MapZones, GeoPixelsTraceWhereTheMapSawTheEdgeAndOnlyThereWhenNoMaskFired) {
  const TableSet& t = *find_table_set("tuned");
  const int map = 0b10000, tables = t.zones(1, 0, 0);
  ASSERT_NE(tables | map, tables);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, 0, /*geo=*/true, GeoPolicy::Split, false, map), tables | map);
  EXPECT_EQ(decide_zones(t, 1, 0, 0, 0, 0, /*geo=*/false, GeoPolicy::Split, false, map), tables);
  EXPECT_EQ(decide_zones(t, 0, 0, 0, 0, 0b00100, /*geo=*/true, GeoPolicy::Split, false, map), map | 0b00100);
  EXPECT_EQ(decide_zones(t, 0, 0, 0, 0b00001, 0, /*geo=*/true, GeoPolicy::Paper, false, map), map | 0b00001);
  EXPECT_EQ(decide_zones(t, 0, 0, 0, 0, 0, /*geo=*/true, GeoPolicy::Split, false, 0), kAllZones);
  EXPECT_EQ(decide_zones(t, 0, 0, 0, 0, 0, /*geo=*/true, GeoPolicy::All, false, map), kAllZones);
  EXPECT_EQ(decide_zones(t, 0, 0, 0, 0, 0, /*geo=*/false, GeoPolicy::Split, true, map), kAllZones);
}

// The map's zones are in the map's frame (kGeoAlongX: the vertical one): they count in a geo
// pixel only where the pixel is oriented in that frame, never as zones of the other.
TEST(MapZones, CountOnlyInAPixelOrientedInTheMapsFrame) {
  // A vertical edge at x = 3.5: level 1 orients column 3 horizontally (a0, a1), and the
  // paper's tables trace its zone 2 alone (b = c1 = 1001, c0 = 0): 9 rays.
  const test::AxisEdgeSource edge{true, 3.5f, 0.0f, 1.0f};
  AdaptiveSettings s;
  s.geo_zones = true;
  auto rays_of_column_3 = [&](uint8_t flag) {
    GeoMap geo{8, 4, std::vector<uint8_t>(32, 0)};
    for (int y = 0; y < 4; ++y) geo.flags[size_t(y) * 8 + 3] = flag;
    const Film f = test::render(edge, 8, 4, s, 64, 1, geo);
    std::vector<int> rays;
    for (int y = 0; y < 4; ++y) rays.push_back(f.rays[size_t(y) * 8 + 3]);
    return rays;
  };
  const uint8_t zone0 = uint8_t(1 << kGeoZoneShift);
  EXPECT_EQ(rays_of_column_3(kGeoEdge), std::vector<int>(4, 9));
  // The map's zone 0 in the horizontal frame: traced too.
  EXPECT_EQ(rays_of_column_3(kGeoEdge | zone0), std::vector<int>(4, 13));
  // Its zone 0 in the vertical frame is another strip of the pixel: the tables' zones alone.
  EXPECT_EQ(rays_of_column_3(kGeoEdge | kGeoAlongX | zone0), std::vector<int>(4, 9));
}

}  // namespace
}  // namespace zz
