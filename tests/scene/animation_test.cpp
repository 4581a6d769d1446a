// Keyframe sampling against hand-computed values (glTF 2.0 spec, Appendix C).
#include <gtest/gtest.h>

#include <cmath>

#include "scene/animation.h"

namespace zz {
namespace {

AnimationChannel channel(AnimatedProperty p, Interpolation i, std::vector<float> times, std::vector<glm::vec4> values) {
  AnimationChannel c;
  c.node = 0;
  c.property = p;
  c.interpolation = i;
  c.times = std::move(times);
  c.values = std::move(values);
  return c;
}

void expect_near(glm::vec4 got, glm::vec4 want, float tol = 1e-6f) {
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], want[k], tol) << "component " << k;
}

glm::vec4 axis_angle_y(float degrees) {  // (x, y, z, w) as glTF stores it
  const float h = glm::radians(degrees) * 0.5f;
  return {0.0f, std::sin(h), 0.0f, std::cos(h)};
}

TEST(Animation, LinearTranslationAndClamping) {
  const auto c = channel(AnimatedProperty::Translation, Interpolation::Linear, {1.0f, 3.0f},
                         {{0, 0, 0, 0}, {4, 2, -2, 0}});
  expect_near(sample(c, 1.5f), {1, 0.5f, -0.5f, 0});
  expect_near(sample(c, 2.0f), {2, 1, -1, 0});
  expect_near(sample(c, 0.0f), {0, 0, 0, 0});   // before the first key: the first value
  expect_near(sample(c, 7.0f), {4, 2, -2, 0});  // after the last: the last
  expect_near(sample(c, NAN), {0, 0, 0, 0});
}

TEST(Animation, StepHoldsUntilTheNextKey) {
  const auto c = channel(AnimatedProperty::Scale, Interpolation::Step, {0.0f, 1.0f, 2.0f},
                         {{1, 1, 1, 0}, {2, 2, 2, 0}, {3, 3, 3, 0}});
  EXPECT_EQ(sample(c, 0.999f).x, 1.0f);
  EXPECT_EQ(sample(c, 1.0f).x, 2.0f);
  EXPECT_EQ(sample(c, 1.5f).x, 2.0f);
  EXPECT_EQ(sample(c, 2.0f).x, 3.0f);
  EXPECT_EQ(sample(c, 9.0f).x, 3.0f);
}

TEST(Animation, CubicSplineTangentsAreScaledByTheKeyInterval) {
  // Keys at t = 1 and 3 (interval 2): v0 = 1 with out-tangent 1, v1 = 3 with in-tangent -1.
  // At u = 0.5: h00 = h01 = 0.5, h10 = u³-2u²+u = 0.125, h11 = u³-u² = -0.125, so
  // p = 0.5*1 + 0.125*2*1 + 0.5*3 + (-0.125)*2*(-1) = 2.5 (unscaled tangents give 2.25).
  const auto c = channel(AnimatedProperty::Translation, Interpolation::CubicSpline, {1.0f, 3.0f},
                         {{9, 9, 9, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}, {-1, 0, 0, 0}, {3, 0, 0, 0}, {9, 9, 9, 0}});
  EXPECT_NEAR(sample(c, 2.0f).x, 2.5f, 1e-6f);
  // u = 0.25: h00 = 0.84375, h10 = 0.140625, h01 = 0.15625, h11 = -0.046875.
  EXPECT_NEAR(sample(c, 1.5f).x, 0.84375f + 0.28125f + 0.46875f + 0.09375f, 1e-6f);
  // The tangents of the first key's in-side and the last key's out-side never matter.
  EXPECT_EQ(sample(c, 1.0f).x, 1.0f);
  EXPECT_EQ(sample(c, 3.0f).x, 3.0f);
  EXPECT_EQ(sample(c, 0.0f).x, 1.0f);
}

TEST(Animation, LinearRotationIsSlerp) {
  const auto c = channel(AnimatedProperty::Rotation, Interpolation::Linear, {0.0f, 1.0f},
                         {axis_angle_y(0.0f), axis_angle_y(90.0f)});
  expect_near(sample(c, 0.5f), axis_angle_y(45.0f));
  // Slerp is uniform in angle; a normalised lerp would give 21.6° at u = 0.25.
  expect_near(sample(c, 0.25f), axis_angle_y(22.5f));
  EXPECT_NEAR(glm::length(sample(c, 0.3f)), 1.0f, 1e-6f);
}

TEST(Animation, SlerpTakesTheShortestPath) {
  // -q is the same 90° rotation; the long way round would pass through -135° at u = 0.5.
  const auto c = channel(AnimatedProperty::Rotation, Interpolation::Linear, {0.0f, 1.0f},
                         {axis_angle_y(0.0f), -axis_angle_y(90.0f)});
  const glm::vec4 q = sample(c, 0.5f);
  EXPECT_NEAR(std::abs(glm::dot(q, axis_angle_y(45.0f))), 1.0f, 1e-6f);
}

TEST(Animation, RotationsAreNormalised) {
  // Unnormalised keys (glTF requires unit quaternions, files do not always comply) and a
  // cubic spline, whose blend is not unit length by construction.
  const auto step = channel(AnimatedProperty::Rotation, Interpolation::Step, {0.0f}, {{0, 2, 0, 0}});
  expect_near(sample(step, 0.0f), {0, 1, 0, 0});
  const auto cubic = channel(AnimatedProperty::Rotation, Interpolation::CubicSpline, {0.0f, 1.0f},
                             {{0, 0, 0, 0}, axis_angle_y(0), {0, 1, 0, 0}, {0, 1, 0, 0}, axis_angle_y(90), {0, 0, 0, 0}});
  EXPECT_NEAR(glm::length(sample(cubic, 0.4f)), 1.0f, 1e-6f);
}

TEST(Animation, PoseReplacesOnlyAnimatedProperties) {
  Animation a;
  a.channels.push_back(channel(AnimatedProperty::Translation, Interpolation::Linear, {0.0f, 2.0f},
                               {{0, 0, 0, 0}, {2, 0, 0, 0}}));
  NodePose rest;
  rest.scale = glm::vec3(3.0f);
  rest.translation = glm::vec3(9.0f);
  const NodePose p = a.pose(0, rest, 1.0f);
  EXPECT_EQ(p.translation, glm::vec3(1, 0, 0));
  EXPECT_EQ(p.scale, glm::vec3(3.0f));
  EXPECT_TRUE(a.animates(0));
  EXPECT_FALSE(a.animates(1));
  EXPECT_EQ(a.end_time(), 2.0f);
  // M = T * R * S applied to (1, 0, 0): scaled by 3, then moved by 1 along x.
  EXPECT_EQ(glm::vec3(p.matrix() * glm::vec4(1, 0, 0, 1)), glm::vec3(4, 0, 0));
}

// Keys closer than the slerp's straight-lerp threshold (cos > 0.9995, under ~3.6 degrees)
// still run from the first key to the second (glTF 2.0 Appendix C: slerp(v_k, v_k+1, t)).
TEST(Animation, NearlyEqualRotationKeysRunFromTheFirstKeyToTheSecond) {
  const auto c = channel(AnimatedProperty::Rotation, Interpolation::Linear, {0.0f, 1.0f},
                         {axis_angle_y(0.0f), axis_angle_y(2.0f)});
  expect_near(sample(c, 0.25f), axis_angle_y(0.5f), 1e-6f);
  expect_near(sample(c, 0.75f), axis_angle_y(1.5f), 1e-6f);
  // The same, across the sign flip to the shorter arc.
  const auto flipped = channel(AnimatedProperty::Rotation, Interpolation::Linear, {0.0f, 1.0f},
                               {axis_angle_y(0.0f), -axis_angle_y(2.0f)});
  EXPECT_NEAR(std::abs(glm::dot(sample(flipped, 0.25f), axis_angle_y(0.5f))), 1.0f, 1e-6f);
}

// An animation ends at the latest key of any of its channels, whatever their order
// (the frame range of an animated scene runs to it).
TEST(Animation, EndTimeIsTheLatestKeyOfAnyChannel) {
  Animation a;
  a.channels.push_back(channel(AnimatedProperty::Translation, Interpolation::Linear, {0.0f, 5.0f},
                               {{0, 0, 0, 0}, {1, 0, 0, 0}}));
  a.channels.push_back(channel(AnimatedProperty::Scale, Interpolation::Linear, {0.0f, 2.0f},
                               {{1, 1, 1, 0}, {2, 2, 2, 0}}));
  EXPECT_EQ(a.end_time(), 5.0f);
  EXPECT_EQ(Animation{}.end_time(), 0.0f);
}

TEST(Animation, FrameRange) {
  EXPECT_EQ(last_frame(2.0f, 24.0), 48);
  EXPECT_EQ(last_frame(47.0f / 24.0f, 24.0), 47);  // float key time, no extra frame
  EXPECT_EQ(last_frame(1.01f, 24.0), 25);
  EXPECT_EQ(last_frame(0.0f, 24.0), 0);
}

// A time is on a frame within 1e-6 of a frame's length, absolute: 0.0416667 s is frame 1 at
// 24 fps, 0.04167 s (1.00008 frames) none; none below 0 or past the largest frame number.
TEST(Animation, FrameAtATime) {
  EXPECT_EQ(frame_at(0.0416667, 24.0), 1);
  EXPECT_EQ(frame_at(1.0, 24.0), 24);
  EXPECT_EQ(frame_at(0.0, 24.0), 0);
  EXPECT_EQ(frame_at(0.04167, 24.0), std::nullopt);
  EXPECT_EQ(frame_at(1.01, 24.0), std::nullopt);
  EXPECT_EQ(frame_at(-1.0, 24.0), std::nullopt);
  EXPECT_EQ(frame_at(double(kMaxFrame) / 24.0, 24.0), kMaxFrame);
  EXPECT_EQ(frame_at(double(kMaxFrame) + 1.0, 1.0), std::nullopt);
}

}  // namespace
}  // namespace zz
