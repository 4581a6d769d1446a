#include "scene/lights.h"

#include <gtest/gtest.h>

#include <cmath>

namespace zz {
namespace {

// A direction survives any finite length: glm::normalize squares it, which overflowed past
// ~1e19 (a zero vector) and underflowed below ~1e-19 (the length test failed).
TEST(Lights, UnitDirectionOfAnyFiniteLength) {
  const glm::vec3 want = glm::normalize(glm::vec3(0.0f, -10.0f, -3.0f));
  for (const float scale : {1.0f, 1e20f, 1e30f, 3e38f, 1e-23f, 1e-40f /* denormal */}) {
    SCOPED_TRACE(scale);
    const std::optional<glm::vec3> d = unit_direction(glm::vec3(0.0f, -10.0f, -3.0f) * (scale / 10.0f));
    ASSERT_TRUE(d);
    EXPECT_NEAR(d->x, want.x, 1e-6f);
    EXPECT_NEAR(d->y, want.y, 1e-6f);
    EXPECT_NEAR(d->z, want.z, 1e-6f);
    EXPECT_NEAR(glm::length(*d), 1.0f, 1e-6f);
  }
  EXPECT_FALSE(unit_direction(glm::vec3(0.0f)));
  EXPECT_FALSE(unit_direction(glm::vec3(-0.0f, 0.0f, -0.0f)));
  EXPECT_FALSE(unit_direction(glm::vec3(1.0f, INFINITY, 0.0f)));
  EXPECT_FALSE(unit_direction(glm::vec3(1.0f, NAN, 0.0f)));
  EXPECT_EQ(*unit_direction(glm::vec3(0.0f, 0.0f, -2.0f)), glm::vec3(0.0f, 0.0f, -1.0f));  // exact on an axis
}

TEST(Lights, ProblemsAreWhatKhrLightsPunctualForbids) {
  Light l;
  EXPECT_EQ(light_problem(l), "");
  l.intensity = glm::vec3(1.0f, -0.5f, 1.0f);
  EXPECT_NE(light_problem(l).find("negative colour or intensity"), std::string::npos);
  l.intensity = glm::vec3(1e30f);  // a rig's largest number
  EXPECT_EQ(light_problem(l), "");
  l.intensity = glm::vec3(1.0f, 3e38f, 1.0f);  // a glTF's intensity may reach float's range
  EXPECT_NE(light_problem(l).find("above 1e30"), std::string::npos);
  l.intensity = glm::vec3(0.0f);  // black is allowed: it lights nothing (can_light)
  EXPECT_EQ(light_problem(l), "");
  l.range = -1.0f;
  EXPECT_NE(light_problem(l).find("negative range"), std::string::npos);
  l = Light{};
  l.type = Light::Type::Spot;
  l.outer_cone = 0.0f;
  EXPECT_NE(light_problem(l).find("spot cone closed"), std::string::npos);
  l.outer_cone = 0.2f;
  l.inner_cone = 0.3f;  // past the outer: a hard-edged cone, as exporters write it
  EXPECT_EQ(light_problem(l), "");
  l.type = Light::Type::Point;
  l.outer_cone = 0.0f;  // cones are a spot's only
  EXPECT_EQ(light_problem(l), "");
}

// A NaN cone angle is no open cone: refused, as can_light would find it dark.
TEST(Lights, ASpotWithANaNConeIsRefused) {
  Light l;
  l.type = Light::Type::Spot;
  l.outer_cone = std::nanf("");
  EXPECT_FALSE(can_light(l));
  EXPECT_NE(light_problem(l).find("spot cone closed"), std::string::npos);
}

TEST(Lights, CanLightNeedsIntensityAndAnOpenCone) {
  Light l;
  EXPECT_TRUE(can_light(l));
  l.intensity = glm::vec3(0.0f, 0.0f, 1e-3f);
  EXPECT_TRUE(can_light(l));
  l.intensity = glm::vec3(0.0f);
  EXPECT_FALSE(can_light(l));
  l = Light{};
  l.type = Light::Type::Spot;
  EXPECT_TRUE(can_light(l));
  l.outer_cone = 0.0f;
  EXPECT_FALSE(can_light(l));
}

// Every colour channel counts (KHR_lights_punctual: colour in [0, 1] per channel): a pure
// red, green or blue light lights, and a negative value in any one channel is refused.
TEST(Lights, EachColourChannelCountsOnItsOwn) {
  for (int c = 0; c < 3; ++c) {
    SCOPED_TRACE(c);
    Light l;
    l.intensity = glm::vec3(0.0f);
    l.intensity[c] = 2.0f;
    EXPECT_TRUE(can_light(l));
    EXPECT_EQ(light_problem(l), "");
    l.intensity = glm::vec3(1.0f);
    l.intensity[c] = -0.5f;
    EXPECT_NE(light_problem(l).find("negative colour or intensity"), std::string::npos);
  }
}

}  // namespace
}  // namespace zz
