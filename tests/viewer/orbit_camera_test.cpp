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

// The scene camera's pose is kept whole: a rolled camera keeps its roll, and a small drag
// makes a small change (the upright turntable snapped it level: 8100 of 9216 pixels changed
// for one pixel of drag).
TEST(OrbitCamera, RolledAndTopDownCamerasStartWhereTheyAreAndMoveSmoothly) {
  const Camera rolled = Camera::look_at({0.0f, 1.9f, 4.2f}, {0.0f, 0.4f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.7f);
  const Camera down = Camera::look_at({0.0f, 6.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 0.7f);
  for (const Camera& start : {rolled, down, start_camera()}) {
    OrbitCamera orbit(start, 4.0f);
    Camera c = orbit.camera();
    expect_near(c.position, start.position, 1e-4f);
    expect_near(c.forward, start.forward, 1e-5f);
    expect_near(c.up, start.up, 1e-5f);
    expect_near(c.right, start.right, 1e-5f);
    for (const glm::vec2 drag : {glm::vec2(1.0f, 0.0f), glm::vec2(0.0f, 1.0f), glm::vec2(0.0f, -1.0f)}) {
      OrbitCamera step(start, 4.0f);
      step.orbit(drag.x, drag.y, 96);  // one pixel turns by pi / 96
      const Camera s = step.camera();
      EXPECT_LT(glm::length(s.forward - start.forward), 0.04f);
      EXPECT_LT(glm::length(s.up - start.up), 0.04f);
      EXPECT_LT(glm::length(s.right - start.right), 0.04f);
      EXPECT_NEAR(glm::dot(s.forward, s.up), 0.0f, 1e-5f);
      EXPECT_NEAR(glm::dot(glm::cross(s.right, s.up), s.forward), glm::dot(glm::cross(start.right, start.up), start.forward), 1e-5f);
    }
  }
  // Straight down, a horizontal drag spins the view about the vertical; a vertical drag
  // leaves the pole either way and never comes back past the limit.
  OrbitCamera spin(down, 6.0f);
  spin.orbit(48.0f, 0.0f, 96);  // a quarter turn
  expect_near(spin.camera().forward, {0.0f, -1.0f, 0.0f}, 1e-5f);
  EXPECT_NEAR(std::abs(spin.camera().up.x), 1.0f, 1e-5f);  // was -z: a quarter turn about y
  for (const float dy : {10.0f, -10.0f}) {
    OrbitCamera tilt(down, 6.0f);
    tilt.orbit(0.0f, dy, 96);
    EXPECT_GT(tilt.camera().forward.y, -0.99f);  // off the pole
    tilt.orbit(0.0f, -dy * 100.0f, 96);           // back and far beyond
    EXPECT_GE(std::abs(tilt.camera().forward.y), 0.99f);
    EXPECT_LE(std::abs(tilt.camera().forward.y), std::sin(1.55f) + 1e-5f);
  }
}

// A slightly rolled camera can still reach a pole (past about 1.2 degrees of roll the
// view cannot come that close to one): it stops at the limit too.
TEST(OrbitCamera, ARolledCameraStopsShortOfThePoles) {
  const glm::vec3 up = glm::normalize(glm::vec3(0.009f, 1.0f, 0.0f));  // rolled by half a degree
  const Camera start = Camera::look_at({0.0f, 1.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, up, 0.7f);
  ASSERT_GT(std::hypot(start.forward.y, start.up.y), std::sin(1.55f));  // a pole is in reach
  for (const float dy : {1e5f, -1e5f}) {
    OrbitCamera orbit(start, 5.0f);
    orbit.orbit(0.0f, dy, 480);
    const Camera c = orbit.camera();
    EXPECT_LE(std::abs(c.forward.y), std::sin(1.55f) + 1e-5f);
    EXPECT_GT(std::abs(c.forward.y), 0.99f);
    EXPECT_NEAR(glm::dot(c.forward, c.up), 0.0f, 1e-5f);
  }
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

// An orthographic view does not change with distance: the wheel narrows it (ymag), and a
// pan moves by 2 ymag per viewport height at any depth.
TEST(OrbitCamera, AnOrthographicViewZoomsByItsExtentAndPansByIt) {
  Camera start = Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  start.ymag = 2.0f;
  OrbitCamera orbit(start, 5.0f);
  orbit.zoom(2.0f);
  EXPECT_NEAR(orbit.distance(), 5.0f, 1e-6f);
  EXPECT_NEAR(orbit.camera().ymag, 2.0f * 0.85f * 0.85f, 1e-6f);
  orbit.zoom(-2.0f);
  EXPECT_NEAR(orbit.camera().ymag, 2.0f, 1e-5f);
  orbit.pan(200.0f, 0.0f, 400);
  expect_near(orbit.camera().position, {-2.0f, 0.0f, 5.0f}, 1e-5f);
  orbit.orbit(100.0f, 30.0f, 400);
  EXPECT_TRUE(orbit.camera().orthographic()) << "orbiting keeps the camera type";
}

// An orthographic camera's rays start at its plane: a plan view 10 above a scene of radius
// 70 would swing that plane through the scene when orbited to a side view, cutting its near
// half away for good (the wheel narrows the view, nothing moves the plane; review). Its
// orbit stands off beyond the scene's sphere, with the same image and planes at the start.
TEST(OrbitCamera, AnOrthographicOrbitStandsOffBeyondTheScene) {
  Camera plan = Camera::look_at({0, 10, 0}, {0, 0, 0}, {0, 0, -1}, 0.8f);
  plan.ymag = 5.0f;
  plan.znear = 2.0f;
  OrbitCamera orbit = orbit_for(plan, {0, 0, 0}, 70.0f);
  const Camera start = orbit.camera();
  expect_near(start.forward, plan.forward, 1e-6f);
  EXPECT_EQ(start.ymag, plan.ymag);
  EXPECT_NEAR(glm::dot(start.position - plan.position, plan.forward), -63.5f, 1e-3f) << "stood back along the view";
  EXPECT_NEAR(glm::length(glm::cross(start.position - plan.position, plan.forward)), 0.0f, 1e-4f);
  EXPECT_NEAR(start.znear, 65.5f, 1e-3f) << "the near plane stays where it was";
  orbit.orbit(0.0f, 200.0f, 400);  // a quarter turn of pitch: from the plan to a side view
  EXPECT_GE(glm::length(orbit.camera().position), 70.0f) << "the plane stays outside the scene";
  // A pinhole orbits about its focus as before.
  EXPECT_NEAR(orbit_for(Camera::look_at({0, 10, 0}, {0, 0, 0}, {0, 0, -1}, 0.8f), {0, 0, 0}, 70.0f).distance(), 10.0f,
              1e-5f);
}

TEST(OrbitCamera, FocusDistanceIsTheSceneCentreAlongTheView) {
  const Camera c = Camera::look_at({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  EXPECT_NEAR(focus_distance(c, {1.0f, 0.0f, 2.0f}, 3.0f), 8.0f, 1e-5f);
  EXPECT_NEAR(focus_distance(c, {0.0f, 0.0f, 20.0f}, 3.0f), 0.3f, 1e-6f);  // behind: clamp
}

// A vertical drag pans like a horizontal one: the point under the cursor follows it, so a
// drag down (image y grows downwards) moves the camera up by d tan(fov/2) per half height.
TEST(OrbitCamera, AVerticalPanMovesThePointUnderTheCursorWithIt) {
  const Camera start = Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  OrbitCamera orbit(start, 5.0f);
  orbit.pan(0.0f, 200.0f, 400);
  expect_near(orbit.camera().position, {0.0f, 5.0f * std::tan(0.4f), 5.0f}, 1e-4f);
  expect_near(orbit.camera().forward, start.forward, 1e-5f);
}

// The wheel keeps the orbit distance within [1e-4, 1e6]: zooming far out stops there
// instead of reaching infinity (a camera at NaN), zooming in stops short of the target.
TEST(OrbitCamera, ZoomStopsAtItsLimits) {
  OrbitCamera orbit(start_camera(), 4.0f);
  orbit.zoom(-1000.0f);
  EXPECT_EQ(orbit.distance(), 1e6f);
  EXPECT_TRUE(std::isfinite(orbit.camera().position.x));
  orbit.zoom(2000.0f);
  EXPECT_EQ(orbit.distance(), 1e-4f);
}

// An orthographic orbit's stand-off keeps the clipping planes where they were in the scene:
// a camera without a near plane (znear 0) gets none, and a finite far plane moves back
// with the camera.
TEST(OrbitCamera, AnOrthographicStandOffKeepsThePlanesWhereTheyWere) {
  Camera plan = Camera::look_at({0, 10, 0}, {0, 0, 0}, {0, 0, -1}, 0.8f);
  plan.ymag = 5.0f;
  plan.zfar = 30.0f;
  const Camera start = orbit_for(plan, {0, 0, 0}, 70.0f).camera();  // stood back by 63.5
  EXPECT_EQ(start.znear, 0.0f) << "no near plane stays none";
  EXPECT_NEAR(start.zfar, 93.5f, 1e-3f) << "the far plane stays at y = -20";
}

// The clipping planes turn with the orbited view: a scene camera's own clip axis (a glTF
// camera under a sheared node has one) is dropped, so the planes stay normal to forward.
TEST(OrbitCamera, TheClippingPlanesTurnWithTheView) {
  Camera start = Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  start.znear = 1.0f;
  start.clip_axis = glm::vec3(0.0f, 0.0f, -1.0f);
  OrbitCamera orbit(start, 5.0f);
  orbit.orbit(240.0f, 0.0f, 480);  // a quarter turn about +Y: now looking along +x
  const CameraRays rays(orbit.camera(), 8, 8);
  expect_near(rays.clip.forward, orbit.camera().forward, 1e-6f);
  expect_near(rays.clip.forward, {1.0f, 0.0f, 0.0f}, 1e-5f);
}

}  // namespace
}  // namespace zz
