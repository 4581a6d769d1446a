// Level-3 interpolation weights (ALGORITHM.md §6).
#include <gtest/gtest.h>

#include "aa/adaptive_pixel.h"

namespace zz {
namespace {

float weight_of(int k, int source) {
  const int z = zone_of(k), lane = k - 5 * z - 1;
  const ZoneInterp& w = kZoneInterp[z];
  float s = 0;
  for (int i = 0; i < w.count; ++i)
    if (w.source[i] == source) s += w.weight[i][lane];
  return s;
}

TEST(Interpolation, WeightsOfTheSpecTable) {
  struct Row {
    int k;
    int src[3];
    float w[3];
  };
  // ALGORITHM.md §6, literally.
  const Row rows[] = {
      {1, {kSrcA, kSrcC, kSrcE}, {0.576f, 0.224f, 0.2f}},  {2, {kSrcA, kSrcC, kSrcE}, {0.264f, 0.336f, 0.4f}},
      {3, {kSrcA, kSrcC, kSrcE}, {0.064f, 0.336f, 0.6f}},  {4, {kSrcA, kSrcC, kSrcE}, {0.176f, 0.024f, 0.8f}},
      {6, {kSrcE, kSrcG, -1}, {0.8f, 0.2f, 0}},            {7, {kSrcE, kSrcG, -1}, {0.6f, 0.4f, 0}},
      {8, {kSrcE, kSrcG, -1}, {0.4f, 0.6f, 0}},            {9, {kSrcE, kSrcG, -1}, {0.2f, 0.8f, 0}},
      {11, {kSrcG, kSrcF, -1}, {0.8f, 0.2f, 0}},           {12, {kSrcG, kSrcF, -1}, {0.6f, 0.4f, 0}},
      {13, {kSrcG, kSrcF, -1}, {0.4f, 0.6f, 0}},           {14, {kSrcG, kSrcF, -1}, {0.2f, 0.8f, 0}},
      {16, {kSrcF, kSrcH, -1}, {0.8f, 0.2f, 0}},           {17, {kSrcF, kSrcH, -1}, {0.6f, 0.4f, 0}},
      {18, {kSrcF, kSrcH, -1}, {0.4f, 0.6f, 0}},           {19, {kSrcF, kSrcH, -1}, {0.2f, 0.8f, 0}},
      {21, {kSrcH, kSrcB, kSrcD}, {0.8f, 0.024f, 0.176f}}, {22, {kSrcH, kSrcB, kSrcD}, {0.6f, 0.336f, 0.064f}},
      {23, {kSrcH, kSrcB, kSrcD}, {0.4f, 0.336f, 0.264f}}, {24, {kSrcH, kSrcB, kSrcD}, {0.2f, 0.224f, 0.576f}},
  };
  for (const Row& r : rows) {
    float total = 0;
    for (int s = 0; s < 8; ++s) total += weight_of(r.k, s);
    EXPECT_NEAR(total, 1.0f, 1e-6f) << "k " << r.k;
    for (int i = 0; i < 3; ++i)
      if (r.src[i] >= 0) {
        EXPECT_NEAR(weight_of(r.k, r.src[i]), r.w[i], 1e-6f) << "k " << r.k << " source " << i;
      }
  }
}

// A colour linear in canonical u (any v) is reproduced exactly by the interpolation.
TEST(Interpolation, ExactForColourLinearInU) {
  struct Never {
    Rgb4 sample4(float4, float4) {
      ADD_FAILURE() << "no zone should be traced";
      return {};
    }
  } never;
  auto f = [](float u, int c) { return 0.3f + (0.5f + 0.25f * c) * u; };
  // Interpolation runs on the canonical lattice (u along the zigzag): the orientation only
  // places the traced points, which `never` refuses, so one orientation covers both.
  Level2 l2;  // horizontal (UBSan: an orientation left unset indexed the tables out of bounds)
  {
    // Canonical corners A (u=0), B (u=1), C (u=0), D (u=1); E, F, G, H at u .2 .6 .4 .8.
    l2.corners = {float4(f(0, 0), f(1, 0), f(0, 0), f(1, 0)), float4(f(0, 1), f(1, 1), f(0, 1), f(1, 1)),
                  float4(f(0, 2), f(1, 2), f(0, 2), f(1, 2))};
    l2.efgh = {float4(f(.2f, 0), f(.6f, 0), f(.4f, 0), f(.8f, 0)), float4(f(.2f, 1), f(.6f, 1), f(.4f, 1), f(.8f, 1)),
               float4(f(.2f, 2), f(.6f, 2), f(.4f, 2), f(.8f, 2))};
    alignas(16) float4 lattice[kLatticePoints];
    trace_level3(never, float4(0.0f), float4(0.0f), l2, 0, lattice);
    for (int k = 0; k < kLatticePoints; ++k)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(lattice[k][c], f(k / 25.0f, c), 1e-6f) << "k " << k << " c " << c;
  }
}

}  // namespace
}  // namespace zz
