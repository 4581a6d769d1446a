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

}  // namespace
}  // namespace zz
