// offset_ray_origin (Waechter & Binder, Ray Tracing Gems ch. 6) and the re-intersection
// test of pbrt-v4's tests: a ray leaving a hit point never hits its own triangle.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/bvh.h"
#include "test_meshes.h"

namespace zz {
namespace {

TEST(RayOffset, MovesAlongTheNormalByUlps) {
  glm::vec3 p(1.0f, -2.0f, 1000.0f), n(0.0f, 0.6f, -0.8f);
  glm::vec3 q = offset_ray_origin(p, n);
  EXPECT_EQ(q.x, p.x);  // zero normal component: unchanged
  EXPECT_GT(q.y, p.y);  // moves towards +n even where p is negative
  EXPECT_LT(q.z, p.z);
  // 256 ULPs per unit normal: 0.6 * 256 = 153 ULPs (towards 0 from -2, where a ULP is
  // 2^-23), 0.8 * 256 = 204 ULPs of 1000 (2^-14 each).
  EXPECT_FLOAT_EQ(q.y - p.y, 153.0f * std::ldexp(1.0f, -23));
  EXPECT_FLOAT_EQ(p.z - q.z, 204.0f * std::ldexp(1.0f, -14));
}

TEST(RayOffset, NearTheOriginUsesAFixedFloatOffset) {
  glm::vec3 q = offset_ray_origin(glm::vec3(0.0f, 0.01f, -0.02f), glm::vec3(1.0f, 0.0f, -1.0f));
  EXPECT_FLOAT_EQ(q.x, 1.0f / 65536.0f);
  EXPECT_EQ(q.y, 0.01f);
  EXPECT_FLOAT_EQ(q.z, -0.02f - 1.0f / 65536.0f);
}

TEST(RayOffset, OffsetScalesWithMagnitudeNotSceneSize) {
  for (float s : {0.04f, 1.0f, 1e4f, 1e8f}) {
    glm::vec3 p(s, s, s), n(0.0f, 0.0f, 1.0f);
    float d = offset_ray_origin(p, n).z - s;
    EXPECT_GT(d, 0.0f);
    EXPECT_LT(d / s, 1e-4f) << s;  // a few hundred ULPs, relative
  }
}

// pbrt-v4 style: random triangles from 1e-8 to 1e8 in size and position, hit from a
// random origin; a ray spawned from the offset hit point to the side it leaves from never
// hits the same triangle.
TEST(RayOffset, SpawnedRaysNeverHitTheirOwnTriangle) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), ex(-8.0f, 8.0f);
  int trials = 0, self_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    float scale = std::pow(10.0f, ex(rng));
    // Even trials: the triangle sits away from the coordinate planes relative to its
    // size; odd trials: it straddles them (hit points much closer to 0 than the vertices).
    glm::vec3 r3(u(rng), u(rng), u(rng));
    glm::vec3 centre = scale * (i % 2 ? 2.0f * r3 - 1.0f : 2.0f + 3.0f * r3);
    if (rng() % 2) centre.x = -centre.x;
    if (rng() % 2) centre.z = -centre.z;
    std::vector<glm::vec3> tri;
    for (int k = 0; k < 3; ++k) tri.push_back(centre + scale * test::random_unit(rng));
    Bvh bvh = Bvh::build(tri);
    glm::vec3 n = glm::normalize(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
    if (!std::isfinite(n.x)) continue;
    // Aim at a random interior point from a random side.
    float b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
    glm::vec3 target = (1.0f - b1 - b2) * tri[0] + b1 * tri[1] + b2 * tri[2];
    glm::vec3 o = target + 4.0f * scale * test::random_unit(rng);
    Hit h = bvh.intersect1(Ray{o, target - o});
    if (!h.hit()) continue;
    glm::vec3 p = (1.0f - h.u - h.v) * tri[0] + h.u * tri[1] + h.v * tri[2];
    // Leave on the side the ray came from (reflection) or the other (transmission).
    glm::vec3 side = glm::dot(o - p, n) > 0.0f ? n : -n;
    if (rng() % 2) side = -side;
    glm::vec3 start = offset_ray_origin(p, side);
    for (int k = 0; k < 4; ++k) {
      glm::vec3 d = test::random_unit(rng);
      if (glm::dot(d, side) < 0.0f) d = -d;
      ++trials;
      self_hits += bvh.intersect1(Ray{start, d}).hit();
    }
  }
  EXPECT_GT(trials, 60000);
  EXPECT_EQ(self_hits, 0);
}

}  // namespace
}  // namespace zz
