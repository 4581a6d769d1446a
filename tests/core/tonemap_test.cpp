#include "core/tonemap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace zz {
namespace {

TEST(ExpNeg4, MatchesLibmOnItsRange) {
  double worst = 0;
  for (float x = -80.0f; x <= 0.0f; x += 0.01f) {
    float got = exp_neg4(float4(x))[0];
    double want = std::exp(double(x));
    worst = std::max(worst, std::abs(got - want) / want);
  }
  EXPECT_LT(worst, 3e-7);
}

TEST(SrgbEncode4, MatchesTheTransferFunction) {
  for (int i = 0; i <= 1000; ++i) {
    float l = i / 1000.0f;
    double want = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
    EXPECT_NEAR(srgb_encode4(float4(l))[0], want, 2e-5) << l;
  }
}

TEST(ToneMap, IsMonotoneAndBounded) {
  ToneMap tm{1.5f};
  float prev = -1.0f;
  for (float c = 0.0f; c < 100.0f; c += 0.05f) {
    float t = tm.apply(c);
    EXPECT_GE(t, prev);
    EXPECT_GE(t, 0.0f);
    EXPECT_LE(t, 1.0f);
    prev = t;
  }
}

TEST(ToneMap, DefinesNonFiniteAndNegativeInputs) {
  ToneMap tm{1.0f};
  EXPECT_EQ(tm.apply(std::numeric_limits<float>::quiet_NaN()), 0.0f);
  EXPECT_EQ(tm.apply(-std::numeric_limits<float>::infinity()), 0.0f);
  EXPECT_EQ(tm.apply(-5.0f), 0.0f);
  EXPECT_NEAR(tm.apply(std::numeric_limits<float>::infinity()), 1.0f, 1e-6f);
  EXPECT_NEAR(tm.apply(1e30f), 1.0f, 1e-6f);
}

TEST(ToneMap, KnownValue) {
  // exposure 1, c = ln 2: 1 - exp(-ln2) = 0.5 -> sRGB(0.5) = 0.735357
  ToneMap tm{1.0f};
  EXPECT_NEAR(tm.apply(std::log(2.0f)), 0.735357f, 3e-5f);
}

// T_e(c) = srgb(1 - exp(-e c)): the exposure scales the radiance, nothing else.
TEST(ToneMap, ExposureScalesTheRadiance) {
  for (float e : {0.25f, 0.5f, 2.0f, 3.0f, 8.0f}) {
    const ToneMap scaled{e}, unit{1.0f};
    for (float c : {1e-4f, 0.01f, 0.1f, 0.37f, 1.0f, 2.5f, 10.0f}) {
      // Powers of two scale exactly in float; the others round e * c once, either way.
      EXPECT_NEAR(scaled.apply(c), unit.apply(e * c), 1e-6f) << e << " " << c;
    }
  }
  // Closed form at exposure 2, in double: c = ln(2) / 2 -> 1 - exp(-ln 2) = 0.5 ->
  // sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357; c = 1 -> 1 - e^-2 = 0.864665.
  auto srgb = [](double l) { return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055; };
  const ToneMap two{2.0f};
  EXPECT_NEAR(two.apply(float(std::log(2.0) / 2)), srgb(0.5), 3e-5);
  EXPECT_NEAR(srgb(0.5), 0.735357, 1e-6);
  EXPECT_NEAR(two.apply(1.0f), srgb(1.0 - std::exp(-2.0)), 3e-5);
  EXPECT_NEAR(two.apply(0.001f), srgb(1.0 - std::exp(-0.002)), 3e-5);
  // Exposure 2 is not exposure 1: a wrong (ignored) exposure shows.
  EXPECT_GT(two.apply(1.0f) - ToneMap{1.0f}.apply(1.0f), 0.05f);
}

TEST(ToneMap, SlopeCarriesTheExposureOnce) {
  // Chain rule: slope_e(c) = e * slope_1(e c). And against central differences of the float
  // operator: the step moves u = 1 - exp(-e c) by 2e-3 (8 segments of the sRGB table, whose
  // piecewise-linear slope is not the derivative's; truncation error then < 0.2 %).
  for (float e : {0.5f, 2.0f, 4.0f}) {
    const ToneMap tm{e}, unit{1.0f};
    for (float c : {0.05f, 0.2f, 0.5f, 1.0f}) {
      const float slope = tm.slope4(float4(c))[0];
      EXPECT_NEAR(slope, e * unit.slope4(float4(e * c))[0], 1e-5f * slope) << e << " " << c;
      const float h = float(2e-3 / (e * std::exp(-double(e) * c)));
      const double fd = (double(tm.apply(c + h)) - double(tm.apply(c - h))) / (2.0 * double(h));
      EXPECT_NEAR(slope, fd, 0.01 * fd) << e << " " << c;
    }
  }
}

TEST(ToneMap, SlopeIsTheDerivative) {
  // Against the derivative of the exact operator in double (finite differences of the float
  // operator drown in the rounding of 1 - exp near 0 and near 1).
  for (double exposure : {0.1, 1.0, 4.0})
    for (double c : {1e-4, 2e-3, 0.05, 0.3, 1.0, 3.0}) {
      const double u = 1.0 - std::exp(-exposure * c);
      const double srgb_slope = u <= 0.0031308 ? 12.92 : 1.055 / 2.4 * std::pow(u, 1.0 / 2.4 - 1.0);
      const double want = exposure * (1.0 - u) * srgb_slope;
      const ToneMap tm{float(exposure)};
      EXPECT_NEAR(tm.slope4(float4(float(c)))[0], want, 0.01 * want) << exposure << " " << c;
    }
}

TEST(ToneMap, NoIncrementBelowEpsOverTheSlopeShows) {
  // The highlight flag skips what cannot show: T(c + x) - T(c) <= 1.02 slope(c) x.
  const ToneMap tm{1.0f};
  for (float c = 0.0f; c < 20.0f; c = c * 1.3f + 1e-4f)
    for (float x = 1e-5f; x < 10.0f; x *= 1.7f)
      EXPECT_LE(tm.apply(c + x) - tm.apply(c), 1.02f * tm.slope4(float4(c))[0] * x + 1e-6f) << c << " " << x;
}

// exp_neg4 is exp(x) for every x <= 0: far below the polynomial's range it underflows to
// (about) 0, never to garbage.
TEST(ExpNeg4, UnderflowsToZeroFarBelowItsRange) {
  for (float x : {-87.5f, -88.0f, -90.0f, -100.0f, -1000.0f, -1e30f, -std::numeric_limits<float>::infinity()}) {
    const float got = exp_neg4(float4(x))[0];
    EXPECT_GE(got, 0.0f) << x;
    EXPECT_LE(got, 2e-38f) << x;
  }
}

// slope4 stays the non-negative bound of the display's change where the display saturates.
TEST(ToneMap, SlopeIsNonNegativeWhereTheDisplaySaturates) {
  for (float e : {1.0f, 4.0f})
    for (float c : {30.0f, 90.0f, 1e3f, 1e30f, std::numeric_limits<float>::infinity()}) {
      const float slope = ToneMap{e}.slope4(float4(c))[0];
      EXPECT_GE(slope, 0.0f) << e << " " << c;
      EXPECT_LE(slope, 1e-12f) << e << " " << c;
    }
}

}  // namespace
}  // namespace zz
