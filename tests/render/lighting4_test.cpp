// The four-lane light_towards (render/lighting4.h) against the scalar one (render/lighting.h)
// it must equal bit for bit: the shader's SoA light loop and the highlight flag's corner
// terms both rely on it.
#include "render/lighting4.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "render/lighting.h"

namespace zz {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::vector<Light> every_kind_of_light() {
  Light point;
  point.position = {0.3f, 1.2f, -0.4f};
  point.intensity = {2.0f, 1.5f, 0.7f};
  Light ranged = point;
  ranged.range = 1.5f;  // the glTF window: some lanes beyond it
  Light spot = point;
  spot.type = Light::Type::Spot;
  spot.direction = {0.1f, -1.0f, 0.2f};
  spot.inner_cone = 0.3f;
  spot.outer_cone = 0.6f;  // lanes inside, in the penumbra and outside
  Light narrow = spot;  // a hard-edged 1-degree cone (inner = outer, as Blender writes)
  narrow.inner_cone = narrow.outer_cone = 0.01745f;
  Light sun;
  sun.type = Light::Type::Directional;
  sun.direction = {0.2f, -1.0f, -0.3f};
  sun.intensity = {3.0f, 3.0f, 2.5f};
  return {point, ranged, spot, narrow, sun};
}

// A spot's axis gets its full intensity, however narrow and hard-edged the cone: the glTF
// sample code's fixed 1 / max(0.001, cos_inner - cos_outer) left a 1-degree hard spot at
// 1/43 of it and a half-degree one at 1/690. Just outside the cone: nothing.
TEST(LightTowards, ANarrowHardSpotIsFullyBrightOnItsAxis) {
  for (float degrees : {0.5f, 1.0f, 5.0f, 45.0f}) {
    Light spot;
    spot.type = Light::Type::Spot;
    spot.position = {0.0f, 0.0f, 2.0f};
    spot.direction = {0.0f, 0.0f, -1.0f};
    spot.inner_cone = spot.outer_cone = glm::radians(degrees);
    glm::vec3 to_light, scale;
    float distance;
    ASSERT_TRUE(light_towards(spot, {0.0f, 0.0f, 0.0f}, to_light, distance, scale)) << degrees;
    EXPECT_FLOAT_EQ(scale.r, 0.25f) << degrees;  // intensity 1 over d^2 = 4
    const float outside = 2.0f * std::tan(glm::radians(degrees) * 1.01f);
    light_towards(spot, {outside, 0.0f, 0.0f}, to_light, distance, scale);
    EXPECT_EQ(scale.r, 0.0f) << degrees;
  }
}

// In the penumbra the spot falls off as KHR_lights_punctual's t^2, t = (cos a - cos outer) /
// (cos inner - cos outer): no scene has a spot light, and squaring t nowhere (scalar and SSE
// paths alike) changed no test.
TEST(LightTowards, ASpotsPenumbraFallsOffAsTheSquareOfItsCosineRamp) {
  Light spot;
  spot.type = Light::Type::Spot;
  spot.position = {0.0f, 0.0f, 2.0f};
  spot.direction = {0.0f, 0.0f, -1.0f};
  spot.inner_cone = 0.3f;
  spot.outer_cone = 0.6f;
  for (const float angle : {0.35f, 0.45f, 0.55f}) {
    const glm::vec3 p(2.0f * std::tan(angle), 0.0f, 0.0f);
    glm::vec3 to_light, scale;
    float distance;
    ASSERT_TRUE(light_towards(spot, p, to_light, distance, scale)) << angle;
    const float t = (std::cos(angle) - std::cos(0.6f)) / (std::cos(0.3f) - std::cos(0.6f));
    const float d2 = glm::dot(p - spot.position, p - spot.position);
    EXPECT_NEAR(scale.r, t * t / d2, 1e-5f * t * t / d2) << angle;
  }
}

// Cones over 3.6 degrees keep the glTF sample code's floor, and so their edge's width: a
// hard 10-degree spot's scale is 1 / 0.001 as before; a 1-degree one's is 2 / (1 - cos).
// KHR_lights_punctual's range window, as the spec recommends: clamp(1 - (d/r)^4, 0, 1) / d^2
// (once, not squared), 0 at and beyond the range.
TEST(LightTowards, TheRangeWindowIsTheSpecs) {
  Light l;
  l.position = {0.0f, 0.0f, 0.0f};
  l.intensity = glm::vec3(1.0f);
  l.range = 2.0f;
  for (const float d : {0.5f, 1.0f, 1.5f, 1.9f, 2.0f, 3.0f}) {
    glm::vec3 to_light, scale;
    float tmax = 0.0f;
    const bool lit = light_towards(l, {d, 0.0f, 0.0f}, to_light, tmax, scale);
    const float r = d / 2.0f, expected = std::max(0.0f, 1.0f - r * r * r * r) / (d * d);
    EXPECT_NEAR(lit ? scale.x : 0.0f, expected, 1e-6f * expected + 1e-9f) << d;
  }
}

// The window holds for any range > 0, a short one (a desk lamp's 0.5 m) too.
TEST(LightTowards, AShortRangeWindowsToo) {
  Light l;
  l.range = 0.5f;
  for (const float d : {0.25f, 0.45f, 0.5f, 0.8f}) {
    glm::vec3 to_light, scale;
    float tmax = 0.0f;
    const bool lit = light_towards(l, {d, 0.0f, 0.0f}, to_light, tmax, scale);
    const float r = d / 0.5f, expected = std::max(0.0f, 1.0f - r * r * r * r) / (d * d);
    EXPECT_NEAR(lit ? scale.x : 0.0f, expected, 1e-6f * expected + 1e-9f) << d;
  }
}

TEST(LightTowards, OnlyNarrowSpotsLeaveTheSpecsFloor) {
  const float c10 = std::cos(glm::radians(10.0f)), c1 = std::cos(glm::radians(1.0f));
  EXPECT_FLOAT_EQ(spot_scale(c10, c10), 1000.0f);
  EXPECT_FLOAT_EQ(spot_scale(std::cos(glm::radians(5.0f)), c10), 1.0f / (std::cos(glm::radians(5.0f)) - c10));
  EXPECT_FLOAT_EQ(spot_scale(c1, c1), 2.0f / (1.0f - c1));
}

TEST(LightTowards4, EqualsTheScalarLightTowardsBitForBitInEveryLane) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-2.0f, 2.0f);
  const glm::vec3 unset(7.0f);  // no unit vector: light_towards left to_light as it was
  for (const Light& light : every_kind_of_light()) {
    const LightConstants constants(light);
    for (int round = 0; round < 2000; ++round) {
      glm::vec3 p[4];
      for (glm::vec3& q : p) q = {coord(rng), coord(rng), coord(rng)};
      if (round == 0) p[2] = light.position;  // at the light: no direction
      if (light.type == Light::Type::Spot && round % 2 == 1)  // on and near the axis: the cone and its edge
        for (int i = 0; i < 4; ++i)
          p[i] = light.position + glm::normalize(light.direction) * (1.0f + float(i)) +
                 glm::vec3(coord(rng), coord(rng), coord(rng)) * (0.01f * float(i));
      alignas(16) float x[4], y[4], z[4];
      for (int i = 0; i < 4; ++i) x[i] = p[i].x, y[i] = p[i].y, z[i] = p[i].z;
      const LightSample4 s =
          light_towards4(light, constants, vec3x4{float4::load(x), float4::load(y), float4::load(z)});
      for (int i = 0; i < 4; ++i) {
        glm::vec3 to_light = unset, scale(0.0f);
        float distance;
        const bool lit = light_towards(light, p[i], to_light, distance, scale);
        const bool towards = to_light != unset;
        ASSERT_EQ(s.lit[i], lit) << int(light.type) << " lane " << i;
        ASSERT_EQ(s.towards[i], towards) << int(light.type) << " lane " << i;
        if (towards) {
          EXPECT_TRUE(same_bits(s.to_light.x[i], to_light.x) && same_bits(s.to_light.y[i], to_light.y) &&
                      same_bits(s.to_light.z[i], to_light.z))
              << int(light.type) << " lane " << i;
        }
        if (lit) {
          EXPECT_TRUE(same_bits(s.scale.x[i], scale.x) && same_bits(s.scale.y[i], scale.y) &&
                      same_bits(s.scale.z[i], scale.z))
              << int(light.type) << " lane " << i;
        }
      }
    }
  }
}

}  // namespace
}  // namespace zz
