// Packet colours (core/color.h): SoA RGB for 4 lanes.
#include "core/color.h"

#include <gtest/gtest.h>

namespace zz {
namespace {

Rgb4 lanes(float r0, float g0, float b0) {
  return {float4(r0, r0 + 1, r0 + 2, r0 + 3), float4(g0, g0 + 1, g0 + 2, g0 + 3), float4(b0, b0 + 1, b0 + 2, b0 + 3)};
}

void expect_eq(const Rgb4& got, const Rgb4& want) {
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(got.r[i], want.r[i]) << "lane " << i;
    EXPECT_EQ(got.g[i], want.g[i]) << "lane " << i;
    EXPECT_EQ(got.b[i], want.b[i]) << "lane " << i;
  }
}

// select(m, a, b): lane i of every channel from a where m is set, else from b; channels never mix.
TEST(Rgb4, SelectTakesEachChannelOfALaneFromTheSameSide) {
  const Rgb4 a = lanes(10, 20, 30), b = lanes(50, 60, 70);
  const mask4 m = float4(1, 0, 1, 0) > float4(0.5f);  // lanes 0 and 2
  expect_eq(select(m, a, b), Rgb4{float4(10, 51, 12, 53), float4(20, 61, 22, 63), float4(30, 71, 32, 73)});
}

// + and * act channel by channel, lane by lane.
TEST(Rgb4, AddAndScaleActPerChannelAndLane) {
  const Rgb4 a = lanes(10, 20, 30), b = lanes(50, 60, 70);
  expect_eq(a + b, Rgb4{float4(60, 62, 64, 66), float4(80, 82, 84, 86), float4(100, 102, 104, 106)});
  expect_eq(a * float4(1, 2, 3, 4), Rgb4{float4(10, 22, 36, 52), float4(20, 42, 66, 92), float4(30, 62, 96, 132)});
}

}  // namespace
}  // namespace zz
