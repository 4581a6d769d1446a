#include "viewer/orbit_camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace zz {
namespace {

void expect_near(glm::vec3 a, glm::vec3 b, float tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Camera start_camera() {
  return Camera::look_at({1.0f, 2.0f, 6.0f}, {0.0f, 0.5f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.7f);
}

TEST(OrbitCamera, StartsAtTheGivenPose) {
  const Camera start = start_camera();
  const OrbitCamera orbit(start, 5.0f);
  const Camera c = orbit.camera();
  expect_near(c.position, start.position, 1e-4f);
  expect_near(c.forward, start.forward, 1e-5f);
  expect_near(c.right, start.right, 1e-5f);
  expect_near(c.up, start.up, 1e-5f);
  EXPECT_EQ(c.yfov, start.yfov);
}

TEST(OrbitCamera, OrbitKeepsTheTargetAndDistance) {
  OrbitCamera orbit(start_camera(), 5.0f);
  const glm::vec3 target = orbit.target();
  orbit.orbit(120.0f, -40.0f, 480);
  const Camera c = orbit.camera();
  EXPECT_NEAR(glm::length(target - c.position), 5.0f, 1e-4f);
  expect_near(glm::normalize(target - c.position), c.forward, 1e-5f);
  // Half a viewport height of horizontal drag turns by ~pi/2 around +Y.
  OrbitCamera quarter(Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.7f), 5.0f);
  quarter.orbit(240.0f, 0.0f, 480);
  expect_near(quarter.camera().position, {-5.0f, 0.0f, 0.0f}, 1e-3f);
}

TEST(OrbitCamera, PitchStopsShortOfThePoles) {
  OrbitCamera orbit(start_camera(), 5.0f);
  orbit.orbit(0.0f, 1e5f, 480);
  const Camera c = orbit.camera();
  EXPECT_TRUE(std::isfinite(c.right.x) && std::isfinite(c.up.y));
  EXPECT_LT(std::abs(c.forward.y), 0.9999f);
  EXPECT_GT(std::abs(c.forward.y), 0.99f);
}

TEST(OrbitCamera, PanMovesThePointUnderTheCursorWithIt) {
  // At the target's depth the image is 2 d tan(fov/2) tall: a drag of h/2 pixels moves the
  // camera by d tan(fov/2) along its right axis (opposite to the drag).
  const Camera start = Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  OrbitCamera orbit(start, 5.0f);
  orbit.pan(200.0f, 0.0f, 400);
  const Camera c = orbit.camera();
  expect_near(c.position, {-5.0f * std::tan(0.4f), 0.0f, 5.0f}, 1e-4f);
  expect_near(c.forward, start.forward, 1e-5f);
}

TEST(OrbitCamera, ZoomScalesTheDistance) {
  OrbitCamera orbit(start_camera(), 4.0f);
  orbit.zoom(2.0f);
  EXPECT_NEAR(orbit.distance(), 4.0f * 0.85f * 0.85f, 1e-5f);
  orbit.zoom(-2.0f);
  EXPECT_NEAR(orbit.distance(), 4.0f, 1e-5f);
}

TEST(OrbitCamera, FocusDistanceIsTheSceneCentreAlongTheView) {
  const Camera c = Camera::look_at({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  EXPECT_NEAR(focus_distance(c, {1.0f, 0.0f, 2.0f}, 3.0f), 8.0f, 1e-5f);
  EXPECT_NEAR(focus_distance(c, {0.0f, 0.0f, 20.0f}, 3.0f), 0.3f, 1e-6f);  // behind: clamp
}

}  // namespace
}  // namespace zz
