// Smooth images cost exactly the corner rays; unrefined pixels are the corner mean.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "aa/analytic.h"
#include "test_sources.h"

namespace zz {
namespace {

uint64_t corner_rays(int w, int h, int tile) {
  uint64_t n = 0;
  for (const TileRect& t : make_tiles(w, h, tile)) n += uint64_t(t.width() + 1) * (t.height() + 1);
  return n;
}

float corner_mean_scalar(float tl, float tr, float bl, float br) { return (((tl + tr) + bl) + br) * 0.25f; }

TEST(AdaptiveSmooth, ConstantAndGradientCostOnlyCorners) {
  const AnalyticImage gradient = make_analytic_image("gradient", 100);
  for (Filter f : {Filter::Box, Filter::Mitchell}) {
    AdaptiveSettings s;
    s.filter = f;
    for (int which = 0; which < 4; ++which) {
      AaStats st;
      const bool field = which < 2;  // level 1 for the frame at once, or per tile
      const Film fb = which % 2 == 0
                          ? test::render(test::ConstantSource{}, 100, 100, s, 64, 1, {}, &st, field)
                          : test::render(AnalyticSource{&gradient}, 100, 100, s, 64, 1, {}, &st, field);
      SCOPED_TRACE(std::string(which % 2 == 0 ? "constant" : "gradient") + (field ? ", field" : ", per tile"));
      for (size_t i = 0; i < fb.rays.size(); ++i) {
        ASSERT_EQ(fb.rays[i], 1);
        ASSERT_EQ(fb.level[i], 1);
      }
      EXPECT_EQ(st.rays[1], 0u);
      EXPECT_EQ(st.rays[2], 0u);
      EXPECT_EQ(st.level2_pixels, 0u);
      EXPECT_EQ(st.pixels, 100u * 100u);
      // Per tile, Mitchell traces the 2-pixel margin of every tile too (counted honestly);
      // the frame's field is its 101 x 101 corners whatever the filter (margins clipped to it).
      const uint64_t own = field ? 101u * 101u : corner_rays(100, 100, 64);
      if (f == Filter::Box || field) {
        EXPECT_EQ(st.rays[0], own);
        EXPECT_EQ(st.margin_rays, 0u);
      } else {
        EXPECT_GT(st.rays[0], own);
        EXPECT_EQ(st.margin_rays, st.rays[0] - own);
      }
    }
  }
}

TEST(AdaptiveSmooth, UnrefinedPixelsAreExactlyTheCornerMean) {
  const AnalyticImage star = make_analytic_image("star", 64);
  const AnalyticImage zp = make_analytic_image("zoneplate", 64);
  for (const AnalyticImage* img : {&star, &zp}) {
    AdaptiveSettings s;
    const Film fb = test::render(AnalyticSource{img}, 64, 64, s, 16);
    int unrefined = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const size_t i = size_t(y) * 64 + x;
        if (fb.level[i] != 1) continue;
        ++unrefined;
        const glm::vec3 tl = img->eval(float(x), float(y)), tr = img->eval(float(x + 1), float(y));
        const glm::vec3 bl = img->eval(float(x), float(y + 1)), br = img->eval(float(x + 1), float(y + 1));
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(fb.radiance[i][c], corner_mean_scalar(tl[c], tr[c], bl[c], br[c])) << x << "," << y;
      }
    EXPECT_GT(unrefined, 200);
  }
}

// A ramp whose display value rises 0.12 per pixel (tone mapping inverted): the corners of
// every pixel differ by more than eps = 0.1, its E..H and corners by at most 0.72 x 0.12.
struct DisplayRampSource {
  Rgb4 sample4(float4 px, float4) const {
    alignas(16) float x[4], out[4];
    px.store(x);
    for (int i = 0; i < 4; ++i) {
      const double d = 0.05 + 0.12 * double(x[i]);
      const double u = d <= 0.04045 ? d / 12.92 : std::pow((d + 0.055) / 1.055, 2.4);
      out[i] = float(-std::log(1.0 - u));  // T^-1 at exposure 1
    }
    const float4 v = float4::load(out);
    return {v, v, v};
  }
};

// A pixel level 1 refines but whose level-2 masks all stay zero traces no zone: it reports
// level 2 and 5 rays (corner + E..H), and all five of its zones count as interpolated.
TEST(AdaptiveSmooth, ARampSteeperThanEpsStopsAtLevelTwo) {
  AdaptiveSettings s;  // the paper's tables, eps 0.1
  AaStats st;
  const Film f = test::render(DisplayRampSource{}, 7, 3, s, 64, 1, {}, &st);
  for (size_t i = 0; i < f.level.size(); ++i) {
    EXPECT_EQ(f.level[i], 2) << "pixel " << i;
    EXPECT_EQ(f.rays[i], 5) << "pixel " << i;
  }
  EXPECT_EQ(st.level2_pixels, 21u);
  EXPECT_EQ(st.level3_pixels, 0u);
  EXPECT_EQ(st.zones_traced, 0u);
  EXPECT_EQ(st.zones_interpolated, 5u * 21u);
  EXPECT_EQ(st.rays[1], 4u * 21u);
  EXPECT_EQ(st.rays[2], 0u);
}

}  // namespace
}  // namespace zz
