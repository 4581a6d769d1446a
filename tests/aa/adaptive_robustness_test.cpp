// HDR values, eps edge cases and odd frame sizes.
#include <gtest/gtest.h>

#include <cmath>

#include "aa/analytic.h"
#include "test_sources.h"

namespace zz {
namespace {

void expect_finite_nonnegative(const Film& f) {
  for (const glm::vec3& c : f.radiance)
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(std::isfinite(c[i]));
      ASSERT_GE(c[i], 0.0f);
    }
}

TEST(AdaptiveRobustness, HdrValuesGiveNoNanOrInf) {
  for (Filter f : {Filter::Box, Filter::Mitchell})
    for (bool all : {false, true}) {
      AdaptiveSettings s;
      s.filter = f;
      s.refine_all = all;
      const Film fb = test::render(test::HdrNoiseSource{}, 37, 29, s, 16);
      expect_finite_nonnegative(fb);
      // 1e9 next to 0 is a discontinuity everywhere: most pixels refine.
      int refined = 0;
      for (uint8_t l : fb.level) refined += l > 1;
      EXPECT_GT(refined, 37 * 29 / 2);
    }
}

TEST(AdaptiveRobustness, EpsExactlyAtTheDistanceIsNoDiscontinuity) {
  // One pixel: left corners p, right corners q.
  const float p = 0.3f, q = 0.37f;
  test::AxisEdgeSource src{true, 0.5f, p, q};
  const ToneMap tm;
  const float d = std::fabs(tm.apply(q) - tm.apply(p));
  AdaptiveSettings s;
  s.eps = d;
  EXPECT_EQ(test::render(src, 1, 1, s).level[0], 1);  // rho == eps: no discontinuity
  s.eps = std::nextafter(d, 0.0f);
  EXPECT_EQ(test::render(src, 1, 1, s).level[0] & 3, 3);  // rho > eps: refined, zones traced
}

TEST(AdaptiveRobustness, EpsZeroAndHuge) {
  const AnalyticImage star = make_analytic_image("star", 32);
  AdaptiveSettings s;
  s.eps = 1e30f;  // nothing is a discontinuity (no geo map): corners only
  AaStats st;
  test::render(AnalyticSource{&star}, 32, 32, s, 64, 1, {}, &st);
  EXPECT_EQ(st.level2_pixels, 0u);
  s.eps = 0.0f;  // a constant image is still continuous (distance 0 <= 0) ...
  test::render(test::ConstantSource{}, 32, 32, s, 64, 1, {}, &st);
  EXPECT_EQ(st.level2_pixels, 0u);
  // ... but any change at all refines.
  const AnalyticImage gradient = make_analytic_image("gradient", 32);
  test::render(AnalyticSource{&gradient}, 32, 32, s, 64, 1, {}, &st);
  EXPECT_EQ(st.level2_pixels, 32u * 32u);
}

TEST(AdaptiveRobustness, OddFrameSizes) {
  const AnalyticImage star = make_analytic_image("star", 256);
  AnalyticSource src{&star};
  for (Filter f : {Filter::Box, Filter::Mitchell}) {
    AdaptiveSettings s;
    s.filter = f;
    for (auto [w, h] : {std::pair{1, 1}, {1, 77}, {77, 1}, {67, 131}, {130, 65}}) {
      SCOPED_TRACE(testing::Message() << w << "x" << h << " " << to_string(f));
      AaStats st;
      const Film a = test::render(src, w, h, s, 64, 2, {}, &st);
      const Film b = test::render(src, w, h, s, 5, 1);
      EXPECT_EQ(st.pixels, uint64_t(w) * h);
      expect_finite_nonnegative(a);
      for (uint8_t r : a.rays) {  // every pixel rendered (0 rays: never written), with at most 25
        EXPECT_GE(r, 1);
        EXPECT_LE(r, 25);
      }
      EXPECT_EQ(a.rays, b.rays);  // 5-pixel tiles on one thread decide every pixel alike
      EXPECT_EQ(a.level, b.level);
      EXPECT_EQ(0, std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec3)));
    }
  }
}

}  // namespace
}  // namespace zz
