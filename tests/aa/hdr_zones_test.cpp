// Zones interpolated across more radiance than the display shows (hdr_zones in
// aa/adaptive_pixel.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "test_sources.h"

namespace zz {
namespace {

// A level-2 pixel of flat radiance `base` with canonical sample `bright` (A B C D E F G H
// = 0..7) set to `value` in channel `channel` (3 = all).
Level2 level2_with(int bright, float value, int channel = 3, float base = 0.2f) {
  alignas(16) float v[3][8];
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 8; ++i) v[c][i] = (i == bright && (channel == 3 || channel == c)) ? value : base;
  Level2 l2{};
  l2.corners = {float4::load(v[0]), float4::load(v[1]), float4::load(v[2])};
  l2.efgh = {float4::load(v[0] + 4), float4::load(v[1] + 4), float4::load(v[2] + 4)};
  return l2;
}

TEST(HdrZones, ABrightSampleFlagsTheZonesInterpolatedFromIt) {
  // §6: z0 from A, C, E; z1 E–G; z2 G–F; z3 F–H; z4 from H, B, D.
  const int want[8] = {/*A*/ 0b00001, /*B*/ 0b10000, /*C*/ 0b00001, /*D*/ 0b10000,
                       /*E*/ 0b00011, /*F*/ 0b01100, /*G*/ 0b00110, /*H*/ 0b11000};
  for (int s = 0; s < 8; ++s) {
    SCOPED_TRACE(s);
    EXPECT_EQ(hdr_zones(level2_with(s, 50.0f), 1.0f), want[s]);
    EXPECT_EQ(hdr_zones(level2_with(s, 50.0f, /*green only*/ 1), 1.0f), want[s]);
    // As dark a sample among bright ones is as wide a span.
    EXPECT_EQ(hdr_zones(level2_with(s, 0.0f, 3, 30.0f), 1.0f), want[s]);
  }
  EXPECT_EQ(hdr_zones(level2_with(0, 0.2f), 1.0f), 0);
}

TEST(HdrZones, SpansWithinTheDisplaysRangeAreLeftToTheTables) {
  // A span of exactly kHdrSpan / exposure is not "more than"; the exposure scales it.
  EXPECT_EQ(hdr_zones(level2_with(0, 1.0f, 3, 0.0f), 1.0f), 0);
  EXPECT_EQ(hdr_zones(level2_with(0, 1.0f, 3, 0.0f), 1.01f), 0b00001);
  EXPECT_EQ(hdr_zones(level2_with(0, 0.5f, 3, 0.0f), 2.0f), 0);
  EXPECT_EQ(hdr_zones(level2_with(0, 0.5f, 3, 0.0f), 2.5f), 0b00001);
}

// Highlights so small that of all 25-point lattice samples only a pixel corner sees them:
// discs of radiance 50 and radius 0.05 px around every third corner, on a wavy background
// within the display's range that puts the pixels around them through many table entries.
struct CornerSpotsSource {
  Rgb4 sample4(float4 px, float4 py) const {
    alignas(16) float x[4], y[4], out[4];
    px.store(x);
    py.store(y);
    for (int i = 0; i < 4; ++i) {
      const float cx = 3.0f * std::round(x[i] / 3.0f), cy = 3.0f * std::round(y[i] / 3.0f);
      const float d2 = (x[i] - cx) * (x[i] - cx) + (y[i] - cy) * (y[i] - cy);
      const float s = std::sin(0.9f * x[i] + 0.4f * y[i]) * std::sin(0.5f * y[i] - 0.7f * x[i]);
      out[i] = d2 < 0.0025f ? 50.0f : 0.3f + 0.25f * s;
    }
    const float4 v = float4::load(out);
    return {v, v, v};
  }
};

TEST(HdrZones, ACornerOnAHighlightIsNotSpreadOverAZone) {
  const CornerSpotsSource spots;
  constexpr int kW = 60, kH = 45;
  AdaptiveSettings s;
  s.tables = find_table_set("tuned");
  s.eps = 0.05f;
  AdaptiveSettings lattice = s;
  lattice.refine_all = true;
  const Film want = test::render(spots, kW, kH, lattice);
  const Film without = test::render(spots, kW, kH, s);
  s.hdr_zones = true;
  const Film with = test::render(spots, kW, kH, s);
  // Error at the pixels around the spots (the rest is the tables' own business).
  double worst_without = 0, worst_with = 0;
  int off_without = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if ((x % 3 != 0 && x % 3 != 2) || (y % 3 != 0 && y % 3 != 2)) continue;
      const size_t i = size_t(y) * kW + x;
      const double e0 = std::abs(without.radiance[i].r - want.radiance[i].r);
      const double e1 = std::abs(with.radiance[i].r - want.radiance[i].r);
      worst_without = std::max(worst_without, e0);
      worst_with = std::max(worst_with, e1);
      off_without += e0 > 0.5;
    }
  // Without the rule some of them spread a corner's 50 over a zone (4 of the 25 points: up
  // to 50 x 1.08 / 25 too much); with it every such zone is traced.
  EXPECT_GT(off_without, 0);
  EXPECT_GT(worst_without, 1.0);
  EXPECT_LT(worst_with, 0.05);
  // The image is a function of each pixel alone: tiles and threads do not change it.
  for (int tile : {7, 16})
    for (int threads : {1, 2}) {
      const Film f = test::render(spots, kW, kH, s, tile, threads);
      EXPECT_EQ(std::memcmp(f.radiance.data(), with.radiance.data(), f.radiance.size() * sizeof(glm::vec3)), 0);
    }
}

// x + 0.6 y < c: black and white (radiance 0 and 1 at exposure 1), an oblique edge within
// the display's range.
struct ObliqueEdgeSource {
  Rgb4 sample4(float4 px, float4 py) const {
    const float4 v = select(px + float4(0.6f) * py < float4(9.3f), float4(0.0f), float4(1.0f));
    return {v, v, v};
  }
};

TEST(HdrZones, AnEdgeWithinTheDisplaysRangeTracesWhatTheTablesSay) {
  const ObliqueEdgeSource edge;
  AdaptiveSettings s;
  s.tables = find_table_set("tuned");
  AaStats off, on;
  const Film a = test::render(edge, 24, 24, s, kTileSize, 1, {}, &off);
  s.hdr_zones = true;
  const Film b = test::render(edge, 24, 24, s, kTileSize, 1, {}, &on);
  EXPECT_GT(off.level2_pixels, 10u);
  EXPECT_EQ(off.zones_traced, on.zones_traced);
  EXPECT_EQ(std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec3)), 0);
}

}  // namespace
}  // namespace zz
