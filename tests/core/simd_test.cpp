#include "core/simd.h"

#include <gtest/gtest.h>

namespace zz {
namespace {

TEST(Simd, ComparisonBitsIndexLanes) {
  float4 a(1, 2, 3, 4), b(2, 2, 2, 2);
  EXPECT_EQ((a < b).bits(), 0b0001);
  EXPECT_EQ((a <= b).bits(), 0b0011);
  EXPECT_EQ((a > b).bits(), 0b1100);
  EXPECT_EQ((!(a > b)).bits(), 0b0011);
}

TEST(Simd, SelectPicksPerLane) {
  float4 r = select(mask4(true, false, true, false), float4(1.0f), float4(2.0f));
  EXPECT_EQ(r[0], 1.0f);
  EXPECT_EQ(r[1], 2.0f);
  EXPECT_EQ(r[2], 1.0f);
  EXPECT_EQ(r[3], 2.0f);
}

TEST(Simd, HorizontalMinMax) {
  float4 a(3, -1, 7, 2);
  EXPECT_EQ(hmin(a), -1.0f);
  EXPECT_EQ(hmax(a), 7.0f);
}

TEST(Simd, NanIsDetected) {
  float4 a(0.0f, __builtin_nanf(""), 1.0f, __builtin_inff());
  EXPECT_EQ(isnan(a).bits(), 0b0010);
  EXPECT_EQ(isfinite(a).bits(), 0b0101);
}

}  // namespace
}  // namespace zz
