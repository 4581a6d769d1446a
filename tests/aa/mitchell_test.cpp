// Mitchell–Netravali filter and its lattice weights (ALGORITHM.md §8).
#include <gtest/gtest.h>

#include <cmath>

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
  // 25 points per pixel area x the filter's unit integral; the residue comes from the
  // lattice's dual frequencies (>= 5 cycles/px), where the Mitchell spectrum is tiny.
  EXPECT_NEAR(total, 25.0, 0.25);
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

}  // namespace
}  // namespace zz
