// offset_ray_origin (pbrt-v4 6.8.6, error-bound offsets) and the re-intersection
// test of pbrt-v4's tests: a ray leaving a hit point never hits its own triangle.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "accel/bvh.h"
#include "test_meshes.h"

namespace zz {
namespace {

// How many of `rays` random rays from `start` into the hemisphere of `side` hit something.
int hits_leaving(const Bvh& bvh, glm::vec3 start, glm::vec3 side, int rays, std::mt19937& rng) {
  int hits = 0;
  for (int k = 0; k < rays; ++k) {
    glm::vec3 d = test::random_unit(rng);
    if (glm::dot(d, side) < 0.0f) d = -d;
    hits += bvh.intersect1(Ray{start, d}).hit();
  }
  return hits;
}

TEST(RayOffset, ErrorBoundScalesWithTheVertices) {
  // A hit at the centroid of a unit triangle placed at distance s from the origin: the
  // bound is ~gamma(8) * s, i.e. a few ULPs of s, whatever the triangle's own size.
  for (float s : {1e-6f, 1.0f, 1e5f, 1e8f}) {
    const glm::vec3 p0(s, s, s), p1(s + 1, s, s), p2(s, s + 1, s);
    const SurfacePosition hit = interpolate_hit(p0, p1, p2, 1.0f / 3.0f, 1.0f / 3.0f);
    EXPECT_GT(hit.error.z, 0.0f);
    EXPECT_LT(hit.error.z, 1e-6f * std::max(s, 1.0f)) << s;
  }
}

TEST(RayOffset, MovesStrictlyToTheNormalSide) {
  const glm::vec3 p0(-3, 1e4f, 2), p1(5, 1e4f, 2), p2(0, 1e4f, 9);
  const SurfacePosition hit = interpolate_hit(p0, p1, p2, 0.25f, 0.5f);
  const glm::vec3 up = offset_ray_origin(hit, {0, 1, 0}), down = offset_ray_origin(hit, {0, -1, 0});
  EXPECT_GT(up.y, hit.p.y);
  EXPECT_LT(down.y, hit.p.y);
  EXPECT_EQ(up.x, hit.p.x);  // zero normal components leave the point alone
  EXPECT_EQ(up.z, hit.p.z);
  EXPECT_LT(up.y - hit.p.y, 1e4f * 1e-5f);  // a few ULPs of 1e4, not a scene epsilon
  // Past the error bound, and every component rounded away from the surface: a normal
  // with a tiny -x part moves x down, never up (mutation testing: next_down stepping the
  // wrong way on negative components passed every test).
  EXPECT_GE(hit.p.y - down.y, hit.error.y);
  const glm::vec3 tilted = offset_ray_origin(hit, glm::normalize(glm::vec3(-1e-6f, 1.0f, 0.0f)));
  EXPECT_LT(tilted.x, hit.p.x);
  EXPECT_GT(tilted.y, hit.p.y);
}

// A point with an error bound of exactly 0 on a plane at 0 still leaves it, to the smallest
// denormal on the normal's side (stepping from +-0), and never stays on the plane.
TEST(RayOffset, APointAtZeroWithNoErrorLeavesThePlane) {
  const SurfacePosition at_zero{glm::vec3(0.0f), glm::vec3(0.0f)};
  const float denorm_min = std::numeric_limits<float>::denorm_min();
  EXPECT_EQ(offset_ray_origin(at_zero, {0, 0, 1}).z, denorm_min);
  EXPECT_EQ(offset_ray_origin(at_zero, {0, 0, -1}).z, -denorm_min);
  const SurfacePosition at_minus_zero{glm::vec3(0.0f, 0.0f, -0.0f), glm::vec3(0.0f)};
  EXPECT_EQ(offset_ray_origin(at_minus_zero, {0, 0, 1}).z, denorm_min);
}

// A coordinate the offset carries past FLT_MAX is +-inf and stays so, never NaN: the step
// away from the surface keeps an infinity in its own direction.
TEST(RayOffset, AnOverflowingCoordinateStaysInfiniteNotNan) {
  const float big = std::numeric_limits<float>::max();
  const SurfacePosition far{glm::vec3(big, -big, 0.0f), glm::vec3(1e38f)};
  const glm::vec3 po = offset_ray_origin(far, glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f)));
  EXPECT_EQ(po.x, std::numeric_limits<float>::infinity());
  EXPECT_EQ(po.y, -std::numeric_limits<float>::infinity());
}

// A triangle in a plane z = +-Z far along z (1e2 to 1e6) but small in x and y: its error
// bound is all in z, so the offset must follow that component (mutation testing: an offset
// from the x and y bounds alone stayed inside the z bound every time, and 40 of 160 000
// spawned rays hit their own triangle; the random triangles below never have one axis so
// much larger than the others).
TEST(RayOffset, AnErrorBoundInOneAxisAloneIsCleared) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int self_hits = 0, trials = 0;
  for (int i = 0; i < 5000; ++i) {
    const float z = (i % 2 ? -1.0f : 1.0f) * std::pow(10.0f, 2.0f + 4.0f * u(rng));
    const std::vector<glm::vec3> tri = {{-1 + 0.1f * u(rng), -1, z}, {1, -1 + 0.1f * u(rng), z}, {0.1f * u(rng), 1, z}};
    const Bvh bvh = Bvh::build(tri);
    float b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
    const SurfacePosition hit = interpolate_hit(tri[0], tri[1], tri[2], b1, b2);
    const glm::vec3 side(0.0f, 0.0f, rng() % 2 ? 1.0f : -1.0f);
    const glm::vec3 start = offset_ray_origin(hit, side);
    ASSERT_GT(std::fabs(start.z - hit.p.z), hit.error.z) << z;
    self_hits += hits_leaving(bvh, start, side, 8, rng);
    trials += 8;
  }
  EXPECT_EQ(trials, 40000);
  EXPECT_EQ(self_hits, 0);
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
    const SurfacePosition hit = interpolate_hit(tri[0], tri[1], tri[2], h.u, h.v);
    // Leave on the side the ray came from (reflection) or the other (transmission).
    glm::vec3 side = glm::dot(o - hit.p, n) > 0.0f ? n : -n;
    if (rng() % 2) side = -side;
    glm::vec3 start = offset_ray_origin(hit, side);
    self_hits += hits_leaving(bvh, start, side, 4, rng);
    trials += 4;
  }
  EXPECT_GT(trials, 60000);
  EXPECT_EQ(self_hits, 0);
}

// Slivers: a triangle a thousand times longer than wide (ToyCar's chrome strips are made of
// them: 0.0165 long, 1.5e-5 wide, 0.01 from the origin). The shear of the watertight test
// rounds at the long side's scale, which is the offset's scale, so t comes out positive for
// rays leaving the offset origin unless hits nearer than t's own error bound are refused:
// without that, 0.4 % of the strips' mirror rays met the facet they left (here 7 %).
TEST(RayOffset, SpawnedRaysNeverHitTheirOwnSliver) {
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int trials = 0, self_hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const glm::vec3 centre = 0.01f * (2.0f * glm::vec3(u(rng), u(rng), u(rng)) - 1.0f);
    const glm::vec3 along = 0.0165f * test::random_unit(rng);
    const glm::vec3 across = 1.5e-5f * glm::normalize(glm::cross(along, test::random_unit(rng)));
    const std::vector<glm::vec3> tri = {centre - 0.5f * along, centre + 0.5f * along, centre + across};
    const Bvh bvh = Bvh::build(tri);
    const glm::vec3 n = glm::normalize(glm::cross(tri[1] - tri[0], tri[2] - tri[0]));
    float b1 = u(rng), b2 = u(rng);
    if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
    const SurfacePosition hit = interpolate_hit(tri[0], tri[1], tri[2], b1, b2);
    const glm::vec3 side = rng() % 2 ? n : -n;
    const glm::vec3 start = offset_ray_origin(hit, side);
    for (int k = 0; k < 8;) {
      glm::vec3 d = test::random_unit(rng);
      if (glm::dot(d, side) < 0.0f) d = -d;
      // At 3 degrees or more off the plane (the strips' rays were 4 to 30); more grazing
      // still, t's error passes any fixed reach (watertight::spawn_reach).
      if (glm::dot(d, side) < 0.05f) continue;
      ++k, ++trials;
      self_hits += bvh.intersect1(Ray{start, d}).hit();
    }
  }
  EXPECT_EQ(trials, 32000);
  EXPECT_EQ(self_hits, 0);
}

}  // namespace
}  // namespace zz
