#include <gtest/gtest.h>

#include <limits>

#include <cmath>

#include "core/error.h"
#include "scene/camera.h"
#include "scene/camera_select.h"
#include "scene/scene.h"

namespace zz {
namespace {

void expect_vec(glm::vec3 a, glm::vec3 b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Camera tilted() { return Camera::look_at({1, 2, 3}, {-2, 0.5f, -4}, {0, 1, 0}, 0.9f); }

TEST(Camera, LookAtBuildsAnOrthonormalRightHandedBasis) {
  Camera c = tilted();
  expect_vec(c.forward, glm::normalize(glm::vec3(-3, -1.5f, -7)));
  EXPECT_NEAR(glm::dot(c.right, c.up), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(c.right, c.forward), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(c.up), 1.0f, 1e-6f);
  expect_vec(glm::cross(c.right, c.up), -c.forward);  // looking down -z in camera space
  EXPECT_GT(c.up.y, 0.0f);
}

TEST(CameraRays, CentrePixelLooksForward) {
  Camera c = tilted();
  CameraRays rays(c, 640, 480);
  expect_vec(rays.origin, c.position);
  expect_vec(rays.direction(320.0f, 240.0f), c.forward);
}

TEST(CameraRays, CornersMatchFieldOfViewAndAspect) {
  Camera c = tilted();
  const int w = 640, h = 480;
  CameraRays rays(c, w, h);
  const float t = std::tan(0.5f * c.yfov);
  auto check = [&](float px, float py, float sx, float sy) {
    glm::vec3 d = rays.direction(px, py);
    float z = glm::dot(d, c.forward);
    EXPECT_NEAR(glm::dot(d, c.right) / z, sx * t * float(w) / float(h), 1e-5f);
    EXPECT_NEAR(glm::dot(d, c.up) / z, sy * t, 1e-5f);
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
  };
  check(0, 0, -1, 1);  // top-left: y grows downwards
  check(float(w), 0, 1, 1);
  check(0, float(h), -1, -1);
  check(float(w), float(h), 1, -1);
}

TEST(CameraRays, PacketMatchesScalarBitForBit) {
  CameraRays rays(tilted(), 333, 217);
  const float xs[4] = {0.5f, 100.25f, 332.9f, 17.0f}, ys[4] = {0.5f, 216.0f, 3.75f, 108.5f};
  float4 dx, dy, dz;
  rays.directions4(float4(xs[0], xs[1], xs[2], xs[3]), float4(ys[0], ys[1], ys[2], ys[3]), dx, dy, dz);
  for (int i = 0; i < 4; ++i) {
    glm::vec3 d = rays.direction(xs[i], ys[i]);
    EXPECT_EQ(d.x, dx[i]);
    EXPECT_EQ(d.y, dy[i]);
    EXPECT_EQ(d.z, dz[i]);
  }
}

TEST(CameraRays, PixelStepsAreSquare) {
  CameraRays rays(tilted(), 800, 200);
  EXPECT_NEAR(glm::length(rays.du), glm::length(rays.dv), 1e-7f);
  EXPECT_NEAR(glm::length(rays.dv), 2.0f * std::tan(0.45f) / 200.0f, 1e-7f);
}

// An orthographic camera (glTF "orthographic", a rig's "ymag"): every ray runs along
// forward, from the plane through the camera's position; the view is 2 ymag tall, its
// width from the frame's shape (square pixels), centred on the position.
TEST(CameraRays, OrthographicRaysAreParallelFromThePlaneThroughThePosition) {
  Camera c = tilted();
  c.ymag = 1.5f;
  ASSERT_TRUE(c.orthographic());
  const int w = 333, h = 217;
  const CameraRays rays(c, w, h);
  ASSERT_TRUE(rays.orthographic);
  const float pixel = 3.0f / float(h);
  const float xs[4] = {0.0f, 333.0f, 166.5f, 17.25f}, ys[4] = {0.0f, 217.0f, 108.5f, 200.0f};
  float4 ox, oy, oz, dx, dy, dz;
  rays.origins4(float4(xs[0], xs[1], xs[2], xs[3]), float4(ys[0], ys[1], ys[2], ys[3]), ox, oy, oz);
  rays.directions4(float4(xs[0], xs[1], xs[2], xs[3]), float4(ys[0], ys[1], ys[2], ys[3]), dx, dy, dz);
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 o = rays.origin_at(xs[i], ys[i]), d = rays.direction(xs[i], ys[i]);
    EXPECT_EQ(o, glm::vec3(ox[i], oy[i], oz[i]));  // scalar and packet agree bit for bit
    EXPECT_EQ(d, glm::vec3(dx[i], dy[i], dz[i]));
    expect_vec(d, c.forward);
    const glm::vec3 rel = o - c.position;
    EXPECT_NEAR(glm::dot(rel, c.forward), 0.0f, 1e-5f) << "on the camera's plane";
    EXPECT_NEAR(glm::dot(rel, c.right), (xs[i] - 0.5f * float(w)) * pixel, 1e-5f);
    EXPECT_NEAR(glm::dot(rel, c.up), (0.5f * float(h) - ys[i]) * pixel, 1e-5f);
  }
  expect_vec(rays.origin_at(0.5f * w, 0.5f * h), c.position, 1e-5f);
  // The clipping planes are depths from that plane, as for a pinhole.
  expect_vec(rays.clip.origin, c.position);
  expect_vec(rays.clip.forward, c.forward);
  // A pinhole's origin is its position in every lane.
  const CameraRays pinhole(tilted(), w, h);
  EXPECT_FALSE(pinhole.orthographic);
  EXPECT_EQ(pinhole.origin_at(17.25f, 200.0f), tilted().position);
}

// --camera NAME picks the one camera of that name; a name two cameras share is refused
// with their indices (it used to pick the first without a word).
TEST(FindCamera, ANameSeveralCamerasShareIsRefusedWithTheirIndices) {
  Scene s;
  for (const char* name : {"wide", "close", "wide"}) {
    s.cameras.push_back(tilted());
    s.cameras.back().name = name;
  }
  EXPECT_EQ(find_camera(s, "close"), 1u);
  EXPECT_EQ(find_camera(s, "2"), 2u);
  try {
    find_camera(s, "wide");
    ADD_FAILURE() << "an ambiguous name was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("camera name 'wide' is ambiguous: cameras 0, 2 have it"), std::string::npos)
        << e.what();
  }
}

// The frame size rule (camera_select.h): the rig's sides, the camera's aspect for a side
// it leaves out, 512 on the longer side; one side from the command line keeps that shape.
TEST(FrameSize, OneSideGivenKeepsTheNaturalFramesShape) {
  Scene rig;  // a rig that sets both sides, 1024 x 1024
  rig.default_width = rig.default_height = 1024;
  rig.width_given = rig.height_given = true;
  Camera square = tilted();
  EXPECT_EQ(frame_size(rig, square).width, 1024);
  EXPECT_EQ(frame_size(rig, square, 96).height, 96);  // a preview, not a 96 x 1024 strip
  EXPECT_EQ(frame_size(rig, square, 0, 50).width, 50);
  EXPECT_EQ(frame_size(rig, square, 96, 40).height, 40);  // both given: those
  rig.default_height = 512;  // a 2:1 rig frame: its shape wins over the camera's aspect
  square.aspect = 1.0f;
  EXPECT_EQ(frame_size(rig, square, 300).height, 150);

  Scene gltf;  // no rig sides: 512 default
  Camera automatic = tilted();  // aspect unknown (0): the default 512 x 512 frame's shape
  EXPECT_EQ(frame_size(gltf, automatic, 64).height, 64);
  EXPECT_EQ(frame_size(gltf, automatic, 0, 64).width, 64);
  Camera wide = tilted();
  wide.aspect = 1.5f;
  EXPECT_EQ(frame_size(gltf, wide).width, 512);
  EXPECT_EQ(frame_size(gltf, wide).height, 341);
  EXPECT_EQ(frame_size(gltf, wide, 300).height, 200);  // exactly the camera's, not 512 / 341's
  EXPECT_EQ(frame_size(gltf, wide, 0, 100).width, 150);

  Scene one_side;  // the rig sets the width; the height follows the camera
  one_side.default_width = 800;
  one_side.width_given = true;
  Camera two = tilted();
  two.aspect = 2.0f;
  EXPECT_EQ(frame_size(one_side, two).height, 400);
  EXPECT_EQ(frame_size(one_side, two, 0, 100).width, 200);
  EXPECT_EQ(frame_size(one_side, two, 16384).height, 8192);
  EXPECT_EQ(frame_size(one_side, two, 0, 16384).width, 16384);  // clamped to the largest side
  // A camera without an aspect takes the frame's: one side from the rig gives a square, as
  // one side from the command line does (exploratory testing: a rig's "height": 100 gave
  // 512 x 100, a 130-degree strip, where --height 100 gave 100 x 100).
  const Camera unknown = tilted();
  EXPECT_EQ(frame_size(one_side, unknown).height, 800);
  Scene tall;
  tall.default_height = 100;
  tall.height_given = true;
  EXPECT_EQ(frame_size(tall, unknown).width, 100);
  EXPECT_EQ(frame_size(tall, unknown, 0, 40).width, 40);
}

// A side from an extreme aspect ratio is still a pixel wide: clamped to [1, the largest
// side] before rounding, never a 0-pixel frame.
TEST(FrameSize, AnExtremeAspectStillGivesAtLeastOnePixel) {
  Scene gltf;
  Camera strip = tilted();
  strip.aspect = 1e6f;
  EXPECT_EQ(frame_size(gltf, strip).width, 512);
  EXPECT_EQ(frame_size(gltf, strip).height, 1);
  EXPECT_EQ(frame_size(gltf, strip, 300).height, 1);
  strip.aspect = 1e-6f;
  EXPECT_EQ(frame_size(gltf, strip).width, 1);
  EXPECT_EQ(frame_size(gltf, strip).height, 512);
  EXPECT_EQ(frame_size(gltf, strip, 0, 300).width, 1);
}

}  // namespace
// Whether a camera's planes can cut into a box: what decides that the map rasterises with
// clip distances and the tracer tests its camera rays' hits.
TEST(CameraClip, CutsIntoABoxOnlyWhereThePlanesCrossIt) {
  CameraClip clip{glm::vec3(0, 0, 5), glm::vec3(0, 0, -1), 2.0f, 8.0f};  // depth = 5 - z
  EXPECT_FALSE(clip.cuts_into({-1, -1, -1}, {1, 1, 1})) << "depths 4..6, inside [2, 8]";
  EXPECT_TRUE(clip.cuts_into({-1, -1, -1}, {1, 1, 4})) << "depths 1..6: the near plane crosses";
  EXPECT_TRUE(clip.cuts_into({-1, -1, -4}, {1, 1, 1})) << "depths 4..9: the far plane crosses";
  EXPECT_FALSE(clip.cuts_into({-1, -1, 6}, {1, 1, 9})) << "behind the camera: out of view anyway";
  EXPECT_FALSE(CameraClip{}.cuts_into({-1, -1, -1}, {1, 1, 1})) << "no planes";
  clip.zfar = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(clip.cuts_into({-1, -1, -1e30f}, {1, 1, 1})) << "an infinite far plane cuts nothing";
  // A Camera's planes reach its rays.
  Camera c = Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.8f);
  c.znear = 0.5f;
  const CameraRays rays(c, 4, 4);
  EXPECT_EQ(rays.clip.znear, 0.5f);
  EXPECT_EQ(rays.clip.depth(glm::vec3(0, 0, 0)), 5.0f);
}

// A box whose nearest corner lies exactly on the near plane (or farthest exactly on the far
// one) counts as cut: the margin covers the rounding of a traced hit's depth, so a hit a
// rounding error nearer than znear is still tested and cut away.
TEST(CameraClip, ABoxTouchingAPlaneCountsAsCut) {
  CameraClip clip{glm::vec3(0, 0, 5), glm::vec3(0, 0, -1), 2.0f, 8.0f};  // depth = 5 - z
  EXPECT_TRUE(clip.cuts_into({-1, -1, -1}, {1, 1, 3})) << "depths 2..6: touches the near plane";
  EXPECT_TRUE(clip.cuts_into({-1, -1, -3}, {1, 1, 1})) << "depths 4..8: touches the far plane";
  EXPECT_FALSE(clip.cuts_into({-1, -1, -1}, {1, 1, 2.99f})) << "depths 2.01..6: inside";
}

}  // namespace zz
