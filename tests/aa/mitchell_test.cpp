// Mitchell–Netravali filter and its lattice weights (ALGORITHM.md §8).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "aa/analytic.h"
#include "aa/mitchell.h"
#include "test_sources.h"

namespace zz {
namespace {

TEST(Mitchell, OneDimensionalValues) {
  EXPECT_NEAR(mitchell1d(0.0), 8.0 / 9.0, 1e-12);   // (6 - 2B) / 6
  EXPECT_NEAR(mitchell1d(1.0), 1.0 / 18.0, 1e-12);  // B / 6
  EXPECT_NEAR(mitchell1d(-1.0), 1.0 / 18.0, 1e-12);
  EXPECT_EQ(mitchell1d(2.0), 0.0);
  EXPECT_EQ(mitchell1d(-2.5), 0.0);
  EXPECT_LT(mitchell1d(1.5), 0.0);  // the negative lobe
  double integral = 0;
  for (int i = 0; i < 40000; ++i) integral += mitchell1d(-2.0 + (i + 0.5) * 1e-4) * 1e-4;
  EXPECT_NEAR(integral, 1.0, 1e-6);
}

TEST(Mitchell, LatticeWeightsNormalisation) {
  const MitchellLatticeWeights& w = mitchell_lattice_weights();
  double total = 0;
  for (int dy = 0; dy < 5; ++dy)
    for (int dx = 0; dx < 5; ++dx) {
      double s = 0, c = 0;
      for (int k = 0; k < 25; ++k) s += w.point[dy][dx][k];
      for (int i = 0; i < 4; ++i) c += w.corner[dy][dx][i];
      EXPECT_NEAR(s, w.sum[dy][dx], 1e-6);
      EXPECT_NEAR(c, w.sum[dy][dx], 1e-6);  // bilinear weights are a partition of unity
      total += s;
    }
  // 25 points per pixel area x the filter's unit integral: 25 within 3e-14 in double, the
  // stored floats' rounding (7e-8) aside. The tolerance was 0.25, blamed on aliasing that
  // is not there.
  EXPECT_NEAR(total, 25.0, 1e-6);
  // The pixel's own corner A sits half a pixel up-left of its centre.
  EXPECT_NEAR(w.point[2][2][0], mitchell1d(-0.5) * mitchell1d(-0.5), 1e-7);
}

TEST(Mitchell, ConstantImageStaysConstant) {
  AdaptiveSettings s;
  s.filter = Filter::Mitchell;
  for (bool all : {false, true}) {
    s.refine_all = all;
    const Film f = test::render(test::ConstantSource{}, 9, 7, s, 4);
    for (const glm::vec3& c : f.radiance) {
      EXPECT_NEAR(c.r, 0.25f, 1e-6f);
      EXPECT_NEAR(c.g, 0.5f, 1e-6f);
      EXPECT_NEAR(c.b, 0.75f, 1e-6f);
    }
  }
}

// ---- An independent double-precision reference of the filter (filters.h's claim) --------
// filters.h: each output pixel is the Mitchell–Netravali filter (B = C = 1/3, radius 2,
// separable, centred on the pixel centre (x + 0.5, y + 0.5)) over every lattice point of
// the pixels around it, normalised by the sum of the weights, clamped at 0. The points are
// those of the rank-1 lattice P_k = (k/25, (7k mod 25)/25) repeated in every pixel that lie
// in the closed frame [0, W] x [0, H] (so the frame's right/bottom corner ring, which only
// holds lattice point k = 0, counts too). With refine_all every such point is traced.

// Mitchell & Netravali (1988) with B = C = 1/3 written out (not mitchell1d):
//   |x| < 1:      (7|x|³ - 12|x|² + 16/3) / 6
//   1 <= |x| < 2: (-7/3 |x|³ + 12|x|² - 20|x| + 32/3) / 6
double mn_ref(double x) {
  x = std::fabs(x);
  if (x < 1) return (7 * x * x * x - 12 * x * x + 16.0 / 3.0) / 6.0;
  if (x < 2) return (-7.0 / 3.0 * x * x * x + 12 * x * x - 20 * x + 32.0 / 3.0) / 6.0;
  return 0;
}

using ScalarImage = std::function<glm::dvec3(float x, float y)>;

// The reference filtered image of `f` sampled at every lattice point of the closed frame.
// Sample positions are rounded to float as the sampler's are (float(x) + float offset), so
// a point next to a step edge lands on the same side; the weights use exact positions.
std::vector<glm::dvec3> mitchell_reference(const ScalarImage& f, int W, int H) {
  std::vector<glm::dvec3> out(size_t(W) * H);
  for (int py = 0; py < H; ++py)
    for (int px = 0; px < W; ++px) {
      const double cx = px + 0.5, cy = py + 0.5;
      glm::dvec3 acc(0.0);
      double wsum = 0;
      for (int qy = std::max(0, py - 3); qy <= std::min(H, py + 3); ++qy)
        for (int qx = std::max(0, px - 3); qx <= std::min(W, px + 3); ++qx)
          for (int k = 0; k < 25; ++k) {
            const int iu = k, iv = (7 * k) % 25;
            // In the closed frame: on the ring x = W or y = H only the integer point.
            if ((qx == W && iu != 0) || (qy == H && iv != 0)) continue;
            const double w = mn_ref(qx + iu / 25.0 - cx) * mn_ref(qy + iv / 25.0 - cy);
            if (w == 0) continue;
            const float sx = float(qx) + float(iu) / 25.0f, sy = float(qy) + float(iv) / 25.0f;
            acc += w * f(sx, sy);
            wsum += w;
          }
      out[size_t(py) * W + px] = glm::max(acc / wsum, glm::dvec3(0.0));
    }
  return out;
}

// Adapts a ScalarImage to a SampleSource.
struct FunctionSource {
  const ScalarImage* f;
  Rgb4 sample4(float4 px, float4 py) const {
    alignas(16) float x[4], y[4], r[4], g[4], b[4];
    px.store(x);
    py.store(y);
    for (int i = 0; i < 4; ++i) {
      const glm::dvec3 c = (*f)(x[i], y[i]);
      r[i] = float(c.r), g[i] = float(c.g), b[i] = float(c.b);
    }
    return {float4::load(r), float4::load(g), float4::load(b)};
  }
};

void expect_matches_reference(const Film& film, const std::vector<glm::dvec3>& ref, double tol, const char* what) {
  ASSERT_EQ(film.radiance.size(), ref.size());
  double worst = 0;
  for (size_t i = 0; i < ref.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::fabs(double(film.radiance[i][c]) - ref[i][c]);
      worst = std::max(worst, d);
      EXPECT_NEAR(film.radiance[i][c], ref[i][c], tol)
          << what << " pixel " << i % size_t(film.width) << "," << i / size_t(film.width) << " channel " << c;
    }
  testing::Test::RecordProperty(std::string(what) + "_max_error", std::to_string(worst));
  std::printf("%s: max |filter - reference| = %.3g\n", what, worst);
}

TEST(Mitchell, StepEdgesMatchTheKernelDefinitionWithRefineAll) {
  // A vertical and a horizontal step, edges away from lattice columns/rows (0.3 = 7.5 x
  // 0.04, 0.7 = 17.5 x 0.04), on a frame with several tiles so tile borders are crossed,
  // plus the negative lobes next to the edge (clamped at 0 on the dark side: a = 0).
  const int W = 13, H = 11;
  const ScalarImage vertical = [](float x, float) { return x < 5.3f ? glm::dvec3(0.0) : glm::dvec3(1.0, 0.5, 0.25); };
  const ScalarImage horizontal = [](float, float y) {
    return y < 6.7f ? glm::dvec3(0.2, 0.3, 0.4) : glm::dvec3(0.9, 0.1, 0.6);
  };
  AdaptiveSettings s;
  s.filter = Filter::Mitchell;
  s.refine_all = true;
  for (int tile : {4, 64}) {
    expect_matches_reference(test::render(FunctionSource{&vertical}, W, H, s, tile),
                             mitchell_reference(vertical, W, H), 1e-5, "vertical");
    expect_matches_reference(test::render(FunctionSource{&horizontal}, W, H, s, tile),
                             mitchell_reference(horizontal, W, H), 1e-5, "horizontal");
  }
  // The reference itself: far from the edge, the image is constant and so is the output;
  // right of the vertical step the overshoot (negative lobe) exceeds the bright level.
  const std::vector<glm::dvec3> ref = mitchell_reference(vertical, W, H);
  EXPECT_NEAR(ref[size_t(5) * W + 0].r, 0.0, 1e-12);
  EXPECT_NEAR(ref[size_t(5) * W + 12].r, 1.0, 1e-12);
  EXPECT_GT(ref[size_t(5) * W + 6].r, 1.0);
}

TEST(Mitchell, StarMatchesTheKernelDefinitionWithRefineAll) {
  // The analytic star (36 wedges) on a 24² frame: edges at every angle.
  const AnalyticImage star = make_analytic_image("star", 24);
  const ScalarImage f = [&](float x, float y) { return glm::dvec3(star.eval(x, y)); };
  AdaptiveSettings s;
  s.filter = Filter::Mitchell;
  s.refine_all = true;
  const std::vector<glm::dvec3> ref = mitchell_reference(f, 24, 24);
  expect_matches_reference(test::render(AnalyticSource{&star}, 24, 24, s, 8), ref, 1e-5, "star");
  // Sanity of the reference: the star is not flat, the filter keeps values near [0, 1].
  double lo = 1, hi = 0;
  for (const glm::dvec3& c : ref) lo = std::min(lo, c.r), hi = std::max(hi, c.r);
  EXPECT_LT(lo, 0.2);
  EXPECT_GT(hi, 0.8);
}

TEST(Mitchell, LinearImagesAreExactWithAndWithoutRefinement) {
  // mitchell.h: an unrefined pixel's points are the bilinear interpolation of its corners
  // (their weights folded into 4 corner weights), which is exact on a linear image: on a
  // gentle gradient (corners differ by < eps, nothing refines) the adaptive image, the
  // refine_all image and the reference all agree.
  const int W = 12, H = 10;
  const ScalarImage gentle = [](float x, float y) {
    return glm::dvec3(0.1 + 0.01 * x + 0.02 * y, 0.6 - 0.015 * x + 0.005 * y, 0.3 + 0.004 * x);
  };
  const std::vector<glm::dvec3> ref = mitchell_reference(gentle, W, H);
  AdaptiveSettings s;
  s.filter = Filter::Mitchell;
  AaStats adaptive_stats;
  s.refine_all = false;
  const Film adaptive = test::render(FunctionSource{&gentle}, W, H, s, 4, 1, {}, &adaptive_stats);
  EXPECT_EQ(adaptive_stats.level2_pixels, 0u);  // the corner shortcut only
  s.refine_all = true;
  const Film all = test::render(FunctionSource{&gentle}, W, H, s, 4);
  for (size_t i = 0; i < ref.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(adaptive.radiance[i][c], all.radiance[i][c], 1e-5) << i << " " << c;
      EXPECT_NEAR(adaptive.radiance[i][c], ref[i][c], 1e-5) << i << " " << c;
    }
  expect_matches_reference(all, ref, 1e-5, "gentle refine_all");

  // A steep HDR gradient (values up to ~8) with refine_all: every point traced. (Not the
  // adaptive run: level 3 interpolates along u towards E..H, which sit at another v, so it
  // is not exact on images varying across u; measured ~4e-3 off here, by design.)
  const ScalarImage steep = [](float x, float y) {
    return glm::dvec3(0.05 + 0.3 * x + 0.1 * y, 4.0 - 0.2 * x + 0.15 * y, 0.5 + 0.25 * y);
  };
  s.refine_all = true;
  expect_matches_reference(test::render(FunctionSource{&steep}, W, H, s, 4), mitchell_reference(steep, W, H), 8e-5,
                           "steep refine_all");  // 1e-5 relative to values up to 8
}

}  // namespace
}  // namespace zz
