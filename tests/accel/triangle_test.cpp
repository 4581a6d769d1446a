// The watertight kernel (Woop et al. 2013) through the BVH: exact values, no culling,
// closed meshes without cracks, degenerate and grazing cases.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/bvh.h"
#include "test_meshes.h"

namespace zz {
namespace {

TEST(Triangle, KnownHitAndBarycentrics) {
  std::vector<glm::vec3> p;
  test::add_tri(p, {0, 0, 1}, {1, 0, 1}, {0, 1, 1});
  Bvh bvh = Bvh::build(p);
  Hit h = bvh.intersect1(Ray{{0.25f, 0.5f, 0.0f}, {0.0f, 0.0f, 1.0f}});
  ASSERT_EQ(h.prim, 0);
  EXPECT_EQ(h.t, 1.0f);
  EXPECT_FLOAT_EQ(h.u, 0.25f);  // weight of vertex 1
  EXPECT_FLOAT_EQ(h.v, 0.5f);   // weight of vertex 2
  // t scales with |dir|; both windings hit (no back-face culling).
  EXPECT_FLOAT_EQ(bvh.intersect1(Ray{{0.25f, 0.5f, 0.0f}, {0.0f, 0.0f, 4.0f}}).t, 0.25f);
  EXPECT_EQ(bvh.intersect1(Ray{{0.25f, 0.5f, 2.0f}, {0.0f, 0.0f, -1.0f}}).prim, 0);
  // Behind the origin, or beyond tmax: no hit. At exactly tmax: hit.
  EXPECT_FALSE(bvh.intersect1(Ray{{0.25f, 0.5f, 2.0f}, {0.0f, 0.0f, 1.0f}}).hit());
  EXPECT_FALSE(bvh.intersect1(Ray{{0.25f, 0.5f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.999f}).hit());
  EXPECT_TRUE(bvh.intersect1(Ray{{0.25f, 0.5f, 0.0f}, {0.0f, 0.0f, 1.0f}, 1.0f}).hit());
  // Outside the triangle: miss.
  EXPECT_FALSE(bvh.intersect1(Ray{{0.6f, 0.6f, 0.0f}, {0.0f, 0.0f, 1.0f}}).hit());
}

// An edge function whose float products cancel to exactly 0 is redone in double (the
// paper's fallback): a ray along z through the origin passes 2^-46 (in edge-function units)
// outside the edge from (-(1 + e), -1) to (1 + 2e, 1 + e), e = 2^-23, where float gives
// (1 + 2e) - (1 + e)^2 = 0. It misses; a ray well inside the triangle hits, in single rays
// and packets alike.
TEST(Triangle, AnEdgeFunctionThatCancelsToZeroInFloatIsSettledInDouble) {
  const float e = std::ldexp(1.0f, -23);
  std::vector<glm::vec3> p;
  test::add_tri(p, {-1, 1, 1}, {-(1 + e), -1, 1}, {1 + 2 * e, 1 + e, 1});
  const Bvh bvh = Bvh::build(p);
  EXPECT_FALSE(bvh.intersect1(Ray{{0, 0, 0}, {0, 0, 1}}).hit());
  EXPECT_EQ(bvh.intersect1(Ray{{-0.5f, 0.2f, 0}, {0, 0, 1}}).prim, 0);
  RayPacket4 r{};
  r.ox = float4(0.0f, -0.5f, 0.0f, -0.5f), r.oy = float4(0.0f, 0.2f, 0.0f, 0.2f), r.oz = float4(0.0f);
  r.dx = r.dy = float4(0.0f), r.dz = float4(1.0f), r.tmax = float4(kInfinity);
  HitPacket4 h;
  bvh.intersect4(r, mask4(true), h);
  EXPECT_EQ(h.prim[0], -1);
  EXPECT_EQ(h.prim[1], 0);
}

// A floor up to 1e7 across, hit at 0.2-2 units from origins near the world's origin (a
// mirror ball resting on it, a contact shadow): the float test's t bound grows with the
// vertices, not with t, and refused these hits, so the ball saw the sky through the floor
// (at 1e6 the camera saw no floor at all). The double-precision re-test finds them. Hits
// within about one rounding step of the vertices (gamma(8) of 1e6 is 0.5) may stay out of
// reach, so the origins rise with the floor's size there: an interpolated hit point could
// not place them. t is as exact as the float coordinates allow, and rays leaving the floor
// from offset origins still never meet it.
TEST(Triangle, NearHitsOnAHugeTriangleAreFound) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), unit(0.0f, 1.0f);
  for (const float size : {1e3f, 1e5f, 1e6f, 1e7f}) {
    std::vector<glm::vec3> p;
    test::add_tri(p, {-size, 0, -size}, {size, 0, size}, {size, 0, -size});
    test::add_tri(p, {-size, 0, -size}, {-size, 0, size}, {size, 0, size});
    Bvh bvh = Bvh::build(p);
    const float lowest = std::max(0.2f, 1e-6f * size);
    int found = 0, self_hits = 0;
    for (int i = 0; i < 500; ++i) {
      const glm::vec3 o(u(rng), lowest + unit(rng), u(rng));
      const glm::vec3 d(u(rng), -0.2f - unit(rng), u(rng));
      const Hit h = bvh.intersect1(Ray{o, d});
      found += h.hit();
      if (!h.hit()) continue;
      EXPECT_NEAR(h.t, o.y / -d.y, gamma(8) * size / -d.y) << "size " << size;
      // Leave from the hit point, offset as the shader does, upwards: never the floor again.
      const size_t t3 = 3 * size_t(h.prim);
      const glm::vec3 up = offset_ray_origin(interpolate_hit(p[t3], p[t3 + 1], p[t3 + 2], h.u, h.v), {0, 1, 0});
      self_hits += bvh.intersect1(Ray{up, glm::vec3(d.x, -d.y, d.z)}).hit();
      self_hits += bvh.occluded1(Ray{up, glm::vec3(-d.z, 1.0f, d.x)});
    }
    EXPECT_EQ(found, 500) << size;
    EXPECT_EQ(self_hits, 0) << size;
  }
}

TEST(Triangle, HitPointReconstructsFromBarycentrics) {
  std::mt19937 rng(17);
  auto p = test::random_soup(rng, 400, 0.5f);
  Bvh bvh = Bvh::build(p);
  int checked = 0;
  for (int i = 0; i < 3000; ++i) {
    glm::vec3 o = 2.0f * test::random_unit(rng);
    Hit h = bvh.intersect1(Ray{o, -o + 0.5f * test::random_unit(rng)});
    if (!h.hit()) continue;
    ++checked;
    EXPECT_GE(h.u, 0.0f);
    EXPECT_GE(h.v, 0.0f);
    EXPECT_LE(h.u + h.v, 1.0f + 1e-6f);
  }
  EXPECT_GT(checked, 1000);
  // Exact geometry: compare the interpolated point to o + t d.
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 o = 2.0f * test::random_unit(rng), d = -o + 0.5f * test::random_unit(rng);
    Hit h = bvh.intersect1(Ray{o, d});
    if (!h.hit()) continue;
    glm::vec3 a = p[3 * size_t(h.prim)], b = p[3 * size_t(h.prim) + 1], c = p[3 * size_t(h.prim) + 2];
    glm::vec3 q = (1.0f - h.u - h.v) * a + h.u * b + h.v * c;
    EXPECT_LT(glm::length(q - (o + h.t * d)), 1e-4f);
  }
}

// Every ray that enters a closed mesh's interior must hit it, also through shared edges
// and vertices: the property Woop's exact edge tests exist for.
int count_leaks(const std::vector<glm::vec3>& mesh, glm::vec3 inside, std::mt19937& rng, int per_target) {
  Bvh bvh = Bvh::build(mesh);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int leaks = 0;
  for (size_t t = 0; t < mesh.size() / 3; ++t) {
    glm::vec3 v[3] = {mesh[3 * t], mesh[3 * t + 1], mesh[3 * t + 2]};
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < per_target; ++j) {
        // Exactly a vertex, or a float point on (or rounded next to) the shared edge.
        glm::vec3 target = j == 0 ? v[k] : v[k] + u(rng) * (v[(k + 1) % 3] - v[k]);
        glm::vec3 from_inside = inside + 0.01f * test::random_unit(rng);
        Ray out{from_inside, target - from_inside};
        leaks += !bvh.intersect1(out).hit();
        leaks += !bvh.occluded1(out);
        // From outside, through the target, towards the interior.
        glm::vec3 far = target + 3.0f * glm::normalize(target - inside) + 0.2f * test::random_unit(rng);
        Ray in{far, target - far};
        leaks += !bvh.intersect1(in).hit();
        RayPacket4 pk;
        pk.ox = float4(in.origin.x), pk.oy = float4(in.origin.y), pk.oz = float4(in.origin.z);
        pk.dx = float4(in.dir.x), pk.dy = float4(in.dir.y), pk.dz = float4(in.dir.z);
        pk.tmax = float4(kInfinity);
        HitPacket4 hp;
        bvh.intersect4(pk, mask4(true), hp);
        leaks += hp.prim[0] < 0;
      }
    }
  }
  return leaks;
}

TEST(Triangle, SphereIsWatertight) {
  std::mt19937 rng(1);
  EXPECT_EQ(count_leaks(test::uv_sphere(48, 24, 1.0f, {0.3f, -0.2f, 0.1f}), {0.3f, -0.2f, 0.1f}, rng, 4), 0);
  EXPECT_EQ(count_leaks(test::uv_sphere(17, 9, 1000.0f, {1e4f, 0, 0}), {1e4f, 0, 0}, rng, 8), 0);
}

TEST(Triangle, CubeIsWatertight) {
  std::mt19937 rng(2);
  EXPECT_EQ(count_leaks(test::cube({-1, -1, -1}, {1, 1, 1}), {0, 0, 0}, rng, 64), 0);
  EXPECT_EQ(count_leaks(test::cube({0.1f, 0.2f, 0.3f}, {0.7f, 0.9f, 1.1f}), {0.4f, 0.55f, 0.7f}, rng, 64), 0);
}

TEST(Triangle, FanHasNoCrackAtItsCenter) {
  std::mt19937 rng(3);
  glm::vec3 c(0.1f, 0.2f, 0.3f);
  Bvh bvh = Bvh::build(test::fan(13, c, 1.0f));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int leaks = 0;
  for (int i = 0; i < 5000; ++i) {
    glm::vec3 o = c + glm::vec3(2.0f * u(rng) - 1.0f, 2.0f * u(rng) - 1.0f, 0.1f + u(rng));
    if (i % 2) o.z = 2.0f * c.z - o.z;  // from below, too
    float a = 6.2831853f * float(i % 13) / 13.0f;
    glm::vec3 target = i % 3 == 0 ? c : c + u(rng) * 0.9f * glm::vec3(std::cos(a), std::sin(a), 0.0f);
    target.z = c.z;
    leaks += !bvh.intersect1(Ray{o, target - o}).hit();
  }
  EXPECT_EQ(leaks, 0);
}

TEST(Triangle, GrazingRaysAreConsistent) {
  std::vector<glm::vec3> p;
  test::add_tri(p, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  Bvh bvh = Bvh::build(p);
  // In the triangle's plane: a degenerate projection, never a hit.
  EXPECT_FALSE(bvh.intersect1(Ray{{-1.0f, 0.25f, 0.0f}, {1.0f, 0.0f, 0.0f}}).hit());
  // Parallel, just above: miss. Nearly parallel, dipping through: hit in front.
  EXPECT_FALSE(bvh.intersect1(Ray{{-1.0f, 0.25f, 1e-6f}, {1.0f, 0.0f, 0.0f}}).hit());
  Hit h = bvh.intersect1(Ray{{-1.0f, 0.25f, 1.25e-6f}, {1.0f, 0.0f, -1e-6f}});
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.t, 1.25f, 1e-3f);
  // Many grazing rays at random: the BVH agrees with brute force bit for bit.
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 2.0f), e(-1e-5f, 1e-5f);
  for (int i = 0; i < 5000; ++i) {
    Ray r{{u(rng), u(rng), e(rng)}, {u(rng), u(rng), e(rng)}};
    Hit a = bvh.intersect1(r), b = test::brute_force(p, r);
    ASSERT_EQ(a.prim, b.prim);
    if (a.hit()) {
      EXPECT_EQ(a.t, b.t);
    }
  }
}

}  // namespace
}  // namespace zz
