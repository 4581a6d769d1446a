// Unrefined pixels to second order (curvature_corrected in aa/adaptive_pixel.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>

#include "test_sources.h"

namespace zz {
namespace {

// f = base + k ((x - cx)^2 + (y - cy)^2), in every channel: smooth, curved, below eps
// between neighbouring corners, so every pixel stays at level 1.
struct BowlSource {
  float base = 0.2f, k = 2e-5f, cx = 20.0f, cy = 13.0f;
  Rgb4 sample4(float4 px, float4 py) const {
    const float4 dx = px - float4(cx), dy = py - float4(cy);
    const float4 v = float4(base) + float4(k) * (dx * dx + dy * dy);
    return {v, v, v};
  }
  // The box integral over [x, x+1] x [y, y+1]: the mean of (t - c)^2 over a unit interval
  // is (x - c)^2 + (x - c) + 1/3.
  double pixel(int x, int y) const {
    auto sq = [](double a) { return a * a + a + 1.0 / 3.0; };
    return base + k * (sq(x - cx) + sq(y - cy));
  }
};

TEST(Curvature, UnrefinedPixelsOfAQuadraticAreItsExactBoxIntegral) {
  const BowlSource bowl;
  AdaptiveSettings s;
  AaStats plain_stats, corrected_stats;
  const Film plain = test::render(bowl, 48, 40, s, 16, 1, {}, &plain_stats);
  s.curvature = true;
  const Film corrected = test::render(bowl, 48, 40, s, 16, 1, {}, &corrected_stats);
  EXPECT_EQ(corrected_stats.level2_pixels, 0u);
  double worst_plain = 0, worst_corrected = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 48; ++x) {
      const double want = bowl.pixel(x, y);
      worst_plain = std::max(worst_plain, std::abs(plain.radiance[size_t(y) * 48 + x].r - want));
      worst_corrected = std::max(worst_corrected, std::abs(corrected.radiance[size_t(y) * 48 + x].r - want));
    }
  // The corner mean is off by f_xx + f_yy over 12 = 4k / 12 everywhere; the correction is
  // exact for a quadratic up to float rounding.
  EXPECT_NEAR(worst_plain, 4.0 * bowl.k / 12.0, 1e-6);
  EXPECT_LT(worst_corrected, 2e-7);
  // The ring, with level 1 for the whole frame: only the frame's own, (W + 3)(H + 3)
  // corners instead of (W + 1)(H + 1), i.e. 2W + 2H + 8 more, counted as margin.
  EXPECT_EQ(plain_stats.margin_rays, 0u);
  EXPECT_EQ(corrected_stats.rays[0] - plain_stats.rays[0], uint64_t(2 * 48 + 2 * 40 + 8));
  EXPECT_EQ(corrected_stats.margin_rays, corrected_stats.rays[0] - plain_stats.rays[0]);
  // Per tile: (w + 3)(h + 3) per w x h tile, 2w + 2h + 8 more each, over the 3 x 3 tiles
  // (16 wide; 16, 16, 8 high); the same image.
  AaStats tiled_plain, tiled_corrected;
  s.curvature = false;
  test::render(bowl, 48, 40, s, 16, 1, {}, &tiled_plain, false);
  s.curvature = true;
  const Film tiled = test::render(bowl, 48, 40, s, 16, 1, {}, &tiled_corrected, false);
  EXPECT_EQ(tiled_corrected.rays[0] - tiled_plain.rays[0], uint64_t(9 * 8 + 2 * (9 * 16 + 3 * (16 + 16 + 8))));
  EXPECT_EQ(tiled_corrected.margin_rays, tiled_corrected.rays[0] - tiled_plain.rays[0]);
  EXPECT_EQ(tiled.radiance, corrected.radiance);
}

TEST(Curvature, AnEdgeBesideThePixelLeavesThePlainMean) {
  // A step one pixel beyond: x < 10 is dark. Pixels 8 and 9 cross or touch it; pixel 10's
  // left outer corner (x = 9) is across the step, so it keeps the corner mean (exactly the
  // constant), while pixel 12, away from it, equals the constant too.
  const test::AxisEdgeSource step{true, 9.5f, 0.0f, 0.5f};
  AdaptiveSettings s;
  s.curvature = true;
  const Film f = test::render(step, 24, 8, s, 8);
  EXPECT_EQ(f.radiance[3 * 24 + 10].r, 0.5f);
  EXPECT_EQ(f.radiance[3 * 24 + 12].r, 0.5f);
}

// The rule itself on a 4 x 4 stencil of corners (stride 4, the pixel's TL corner at (1, 1)),
// every row 0, .10, .14, .10 and every column constant: one curve (not bent: its second
// differences -.06 and -.08 agree), but the outer corner on the left is .10 from its
// neighbour, an edge beyond the pixel at eps .05, so the pixel keeps its mean; at eps .2 the
// same corners are curvature and the mean moves. The same down the columns (the outer
// corner above the pixel is the edge).
TEST(Curvature, AnOuterCornerAcrossEpsIsAnEdgeThoughTheRowOrColumnIsOneCurve) {
  const float curve[4] = {0.0f, 0.10f, 0.14f, 0.10f};
  for (const bool down : {false, true}) {
    float4 corners[16];
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const float v = curve[down ? j : i];
        corners[j * 4 + i] = float4(v, v, v, 0.0f);
      }
    const float4* tl = corners + 5;
    const float4 mean = corner_mean(tl[0], tl[1], tl[4], tl[5]);
    const float4 at_edge = curvature_corrected(mean, tl, tl, 4, float4(0.05f));
    const float4 smooth = curvature_corrected(mean, tl, tl, 4, float4(0.2f));
    EXPECT_EQ(at_edge[0], mean[0]) << (down ? "columns" : "rows");
    EXPECT_NE(smooth[0], mean[0]) << (down ? "columns" : "rows");
  }
}

// A bowl with a faint step at x = 9.5 (0.02 brighter before it, below eps): not curvature.
struct BowlWithFaintStep {
  BowlSource bowl;
  float step = 0.02f;
  Rgb4 sample4(float4 px, float4 py) const {
    const Rgb4 c = bowl.sample4(px, py);
    const float4 v = c.r + select(px < float4(9.5f), float4(step), float4(0.0f));
    return {v, v, v};
  }
};

TEST(Curvature, AFaintStepInTheRingLeavesThePlainMean) {
  // Pixels 8, 9 and 10 have the step between two of the four corners of each row (8: in its
  // ring on the right, 9: inside it, 10: in its ring on the left); the correction would read
  // the step as curvature (its rows' sum of second differences is +-2 step, moving the pixel
  // by step / 24, a display step at 0.02). Pixels 3 to 6 and 12 onwards are on the bowl alone.
  const BowlWithFaintStep source;
  AdaptiveSettings s;
  const Film plain = test::render(source, 48, 40, s, 16);
  s.curvature = true;
  AaStats stats;
  const Film corrected = test::render(source, 48, 40, s, 16, 1, {}, &stats);
  ASSERT_EQ(stats.level2_pixels, 0u);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 48; ++x) {
      const size_t i = size_t(y) * 48 + x;
      if (x >= 8 && x <= 10) {
        EXPECT_EQ(corrected.radiance[i].r, plain.radiance[i].r) << x << "," << y;
      } else if ((x >= 3 && x <= 6) || x >= 12) {
        const double want = source.bowl.pixel(x, y) + (x < 9 ? source.step : 0.0f);
        EXPECT_NEAR(corrected.radiance[i].r, want, 2e-7) << x << "," << y;
      }
    }
}

// 1e9 on every third column of corners, 1e3 elsewhere: the display is white everywhere
// (no two corners differ by eps), but the second differences are HDR steps, not shading.
struct SaturatedColumns {
  Rgb4 sample4(float4 px, float4) const {
    alignas(16) float x[4], v[4];
    px.store(x);
    for (int i = 0; i < 4; ++i) v[i] = std::fmod(std::fabs(x[i]), 3.0f) == 0.0f ? 1e9f : 1e3f;
    const float4 c = float4::load(v);
    return {c, c, c};
  }
};

TEST(Curvature, SaturatedHdrStepsAreNotCurvature) {
  AdaptiveSettings s;
  s.curvature = true;
  const Film f = test::render(SaturatedColumns{}, 30, 8, s, 16);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 30; ++x) {
      const float v = f.radiance[size_t(y) * 30 + x].r;
      ASSERT_EQ(f.level[size_t(y) * 30 + x], 1);
      // Between two 1e3 corners with 1e9 beyond both: the plain mean, not 1e3 - 8e7 -> 0.
      if (x % 3 == 1) {
        EXPECT_EQ(v, 1e3f) << x;
      }
      EXPECT_GE(v, 1e3f) << x;
    }
}

// The rule's bound on a 4 x 4 stencil: a saturated parabola along the rows, 1485.7, 285.7,
// 285.7, 1485.7 (white on the display everywhere: no edge, and one curve), whose correction
// (100) is 0.35 of the pixel's mean (285.7): a quarter of the mean or more is saturated HDR,
// not shading, so the pixel keeps its mean; a tenth of that curvature (correction 10 of a
// mean of 420.7) is corrected.
TEST(Curvature, ACorrectionOfAQuarterOfTheMeanOrMoreLeavesThePlainMean) {
  const ToneMap tonemap;
  auto corrected = [&](float a, float c) {  // rows a + c (i - 1/2)^2, i = -1..2; columns constant
    float4 lin[16], disp[16];
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const float u = float(i - 1) - 0.5f, v = a + c * u * u;
        lin[j * 4 + i] = float4(v, v, v, 0.0f);
        disp[j * 4 + i] = tonemap.apply4(lin[j * 4 + i]);
      }
    const float4 mean = corner_mean(lin[5], lin[6], lin[9], lin[10]);
    return std::pair{mean[0], curvature_corrected(mean, lin + 5, disp + 5, 4, float4(0.05f))[0]};
  };
  const auto [mean, kept] = corrected(135.7f, 600.0f);
  EXPECT_EQ(kept, mean);
  const auto [small_mean, small] = corrected(405.7f, 60.0f);
  EXPECT_NEAR(small, small_mean - 10.0f, 1e-3f);
}

TEST(Curvature, BitIdenticalAcrossTileSizesAndThreads) {
  const BowlSource bowl{0.2f, 3e-5f, 7.3f, 30.1f};
  AdaptiveSettings s;
  s.curvature = true;
  const Film a = test::render(bowl, 70, 45, s, 64, 1);
  for (int tile : {7, 16})
    for (int threads : {1, 2}) {
      const Film b = test::render(bowl, 70, 45, s, tile, threads);
      EXPECT_EQ(0, std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec3)))
          << tile << " " << threads;
    }
}

// bent(): a row of four corners is one curve when its two second differences d1, d2 agree,
// a step when they are opposite; the line between is |d1 - d2| = 0.5 (|d1| + |d2|). Only
// the golden images pinned the 0.5 (mutation testing: 0.6 changed no test).
TEST(Curvature, BentSplitsCurvesFromStepsHalfway) {
  const auto row = [](float d1, float d2) {
    // f(-1), f(0), f(1), f(2) = d1, 0, 0, d2: second differences d1 and d2.
    static float4 q[4];
    q[0] = float4(d1), q[1] = float4(0.0f), q[2] = float4(0.0f), q[3] = float4(d2);
    return bent(q + 1, 1, float4(0.0f));
  };
  EXPECT_EQ(row(1.0f, 1.0f), 0) << "a quadratic";
  EXPECT_EQ(row(1.0f, -1.0f), 0x7) << "a step";
  // Same-signed d2 = x d1 gives |d1 - d2| / (|d1| + |d2|) = (1 - x) / (1 + x).
  const auto x_for = [](float ratio) { return (1.0f - ratio) / (1.0f + ratio); };
  EXPECT_EQ(row(1.0f, x_for(0.45f)), 0) << "ratio 0.45: one curve";
  EXPECT_EQ(row(1.0f, x_for(0.55f)), 0x7) << "ratio 0.55: bent";
  EXPECT_EQ(row(-2.0f, -2.0f * x_for(0.55f)), 0x7) << "either sign";
}

}  // namespace
}  // namespace zz
