// The depth/normal/albedo AOVs' data: the centre ray of each pixel against planes whose
// hit distance, normal and colour are known in closed form.
#include "render/primary_hits.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "test_scenes.h"

namespace zz {
namespace {

constexpr glm::vec3 kWallColour{0.25f, 0.5f, 0.75f};

// A camera at (0, 0, 4) looking down -z at a wall in the plane z = 0 (facing +z); with
// `half`, the wall covers only x <= 0 so the right half of the image misses.
Scene wall_scene(bool half) {
  Scene s;
  s.materials.push_back(test::diffuse_material(kWallColour));
  const float x1 = half ? 0.0f : 10.0f;
  test::add_quad(s, {-10, -10, 0}, {x1, -10, 0}, {x1, 10, 0}, {-10, 10, 0}, 0);
  Light light;
  light.position = {0, 0, 3};
  light.intensity = glm::vec3(10.0f);
  s.lights.push_back(light);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.finalize_materials();
  return s;
}

PrimaryHits trace(const Scene& scene, int w, int h, TileRect region = {}, int threads = 0) {
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  if (region == TileRect{}) region = {0, 0, w, h};
  return trace_primary_hits(shader, scene.cameras[0], w, h, region, threads);
}

TEST(PrimaryHits, CentrePixelSeesTheWallAtItsAnalyticDistance) {
  // 33 x 33: pixel (16, 16)'s centre is the image centre, the camera's axis.
  const PrimaryHits hits = trace(wall_scene(false), 33, 33);
  const size_t centre = 16 * 33 + 16;
  EXPECT_NEAR(hits.depth[centre], 4.0f, 4.0f * 1e-4f);
  EXPECT_EQ(hits.normal[centre], glm::vec3(0, 0, 1));
  EXPECT_EQ(hits.albedo[centre], kWallColour);
}

TEST(PrimaryHits, EveryPixelMatchesTheRayPlaneIntersection) {
  // A wall tilted about the y axis, so the distance varies across the image:
  // plane n . p = 0 with n = (sin a, 0, cos a); the camera ray o + t d meets it at
  // t = -(n . o) / (n . d).
  const float a = 0.4f;
  const glm::vec3 n(std::sin(a), 0.0f, std::cos(a)), along(std::cos(a), 0.0f, -std::sin(a)), up(0, 1, 0);
  Scene s;
  s.materials.push_back(test::diffuse_material(kWallColour));
  const float r = 20.0f;
  test::add_quad(s, -r * along - r * up, r * along - r * up, r * along + r * up, -r * along + r * up, 0);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.6f));
  s.finalize_materials();
  const int w = 40, h = 30;
  const PrimaryHits hits = trace(s, w, h);
  const CameraRays rays(s.cameras[0], w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 d = rays.direction(x + 0.5f, y + 0.5f);
      const float t = -glm::dot(n, rays.origin) / glm::dot(n, d);
      const size_t i = size_t(y) * w + x;
      ASSERT_NEAR(hits.depth[i], t, t * 1e-4f) << x << "," << y;
      EXPECT_NEAR(glm::length(hits.normal[i]), 1.0f, 1e-6f);
      EXPECT_NEAR(glm::dot(hits.normal[i], n), 1.0f, 1e-6f) << x << "," << y;
      EXPECT_EQ(hits.albedo[i], kWallColour);
    }
}

TEST(PrimaryHits, MissesHoldInfinityAndZeros) {
  const int w = 32, h = 24;
  const Scene scene = wall_scene(true);
  const PrimaryHits hits = trace(scene, w, h);
  const CameraRays rays(scene.cameras[0], w, h);
  int missed = 0, hit = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 d = rays.direction(x + 0.5f, y + 0.5f);
      const float wall_x = rays.origin.x + d.x * (-rays.origin.z / d.z);  // where the ray crosses z = 0
      const size_t i = size_t(y) * w + x;
      if (wall_x > 1e-3f) {
        ++missed;
        EXPECT_EQ(hits.depth[i], std::numeric_limits<float>::infinity()) << x << "," << y;
        EXPECT_EQ(hits.normal[i], glm::vec3(0.0f));
        EXPECT_EQ(hits.albedo[i], glm::vec3(0.0f));
      } else if (wall_x < -1e-3f) {
        ++hit;
        EXPECT_TRUE(std::isfinite(hits.depth[i]));
        EXPECT_EQ(hits.albedo[i], kWallColour);
      }
    }
  EXPECT_EQ(missed, w / 2 * h);
  EXPECT_EQ(hit, w / 2 * h);
}

TEST(PrimaryHits, ABackFaceReportsTheNormalTowardsTheCamera) {
  // The wall wound the other way: its normals point away from the camera (-z); the
  // shading normal the shader lights with, and the AOV reports, is turned to +z.
  Scene s;
  s.materials.push_back(test::diffuse_material(kWallColour));
  test::add_quad(s, {-10, -10, 0}, {-10, 10, 0}, {10, 10, 0}, {10, -10, 0}, 0);
  ASSERT_EQ(s.normals[0], glm::vec3(0, 0, -1));
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.finalize_materials();
  const PrimaryHits hits = trace(s, 33, 33);
  for (size_t i = 0; i < hits.normal.size(); ++i) ASSERT_EQ(hits.normal[i], glm::vec3(0, 0, 1)) << i;
  EXPECT_NEAR(hits.depth[16 * 33 + 16], 4.0f, 4.0f * 1e-4f);
}

TEST(PrimaryHits, CutOutSurfacesAreSeenThrough) {
  // A fully cut-out (alpha MASK, alpha 0) sheet at z = 2 in front of the wall: the
  // shader passes it, so depth and albedo are the wall's behind it.
  Scene s = wall_scene(false);
  Material sheet = test::diffuse_material(glm::vec3(1, 0, 0));
  sheet.alpha_mode = AlphaMode::Mask;
  sheet.base_alpha = 0.0f;
  s.materials.push_back(sheet);
  test::add_quad(s, {-10, -10, 2}, {10, -10, 2}, {10, 10, 2}, {-10, 10, 2}, 1);
  s.finalize_materials();
  const PrimaryHits hits = trace(s, 33, 33);
  const size_t centre = 16 * 33 + 16;
  EXPECT_NEAR(hits.depth[centre], 4.0f, 4.0f * 1e-4f);
  EXPECT_EQ(hits.albedo[centre], kWallColour);
}

TEST(PrimaryHits, SameValuesForAnyThreadCountAndRegion) {
  const Scene scene = wall_scene(true);
  const int w = 70, h = 45;
  const PrimaryHits one = trace(scene, w, h, {}, 1), two = trace(scene, w, h, {}, 2);
  EXPECT_EQ(std::memcmp(one.depth.data(), two.depth.data(), one.depth.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(one.normal.data(), two.normal.data(), one.normal.size() * sizeof(glm::vec3)), 0);
  EXPECT_EQ(std::memcmp(one.albedo.data(), two.albedo.data(), one.albedo.size() * sizeof(glm::vec3)), 0);
  // A region's pixels equal the same pixels of the whole frame (odd bounds: partial packets).
  const TileRect region{13, 7, 46, 30};
  const PrimaryHits part = trace(scene, w, h, region, 2);
  ASSERT_EQ(part.width, region.width());
  ASSERT_EQ(part.height, region.height());
  for (int y = region.y0; y < region.y1; ++y)
    for (int x = region.x0; x < region.x1; ++x) {
      const size_t f = size_t(y) * w + x, p = size_t(y - region.y0) * part.width + (x - region.x0);
      ASSERT_EQ(std::memcmp(&part.depth[p], &one.depth[f], sizeof(float)), 0) << x << "," << y;
      ASSERT_EQ(part.normal[p], one.normal[f]);
      ASSERT_EQ(part.albedo[p], one.albedo[f]);
    }
}

}  // namespace
}  // namespace zz
