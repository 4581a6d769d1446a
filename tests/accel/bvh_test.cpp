#include "accel/bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "test_meshes.h"

namespace zz {
namespace {

using test::brute_force;

Ray random_ray(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.5f, 1.5f), t(0.0f, 4.0f);
  Ray r{glm::vec3(u(rng), u(rng), u(rng)), test::random_unit(rng)};
  if (rng() % 3 == 0) r.tmax = t(rng);
  if (rng() % 5 == 0) r.dir *= 7.5f;  // t is in units of |dir|
  return r;
}

void expect_same(const Hit& a, const Hit& b) {
  ASSERT_EQ(a.prim, b.prim);
  if (a.prim < 0) return;
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.u, b.u);
  EXPECT_EQ(a.v, b.v);
}

TEST(Bvh, MatchesBruteForceOnRandomSoups) {
  std::mt19937 rng(7);
  for (int scene = 0; scene < 6; ++scene) {
    auto tris = test::random_soup(rng, 200 + 700 * scene, scene % 2 ? 0.05f : 0.4f);
    BvhBuildStats stats;
    Bvh bvh = Bvh::build(tris, &stats);
    ASSERT_EQ(bvh.triangle_count(), tris.size() / 3);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
      Ray r = random_ray(rng);
      if (i % 2) {  // half of the rays aimed at a triangle, so that hits are common
        size_t t = rng() % (tris.size() / 3);
        r.dir = (tris[3 * t] + tris[3 * t + 1] + tris[3 * t + 2]) / 3.0f - r.origin;
      }
      Hit ref = brute_force(tris, r);
      Hit h = bvh.intersect1(r);
      expect_same(h, ref);
      EXPECT_EQ(bvh.occluded1(r), ref.hit());
      hits += ref.hit();
    }
    EXPECT_GT(hits, 800);  // the rays do exercise hits
  }
}

TEST(Bvh, EqualDistancesGoToTheLowerIndex) {
  // Three copies of one triangle: every hit must report the first copy.
  std::vector<glm::vec3> tris;
  for (int k = 0; k < 3; ++k)
    test::add_tri(tris, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  test::add_tri(tris, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1});
  Bvh bvh = Bvh::build(tris);
  Hit h = bvh.intersect1(Ray{{0.1f, 0.0f, -1.0f}, {0.0f, 0.0f, 1.0f}});
  EXPECT_EQ(h.prim, 0);
  EXPECT_EQ(h.t, 1.0f);
}

TEST(Bvh, ManyCopiesSplitByCountAndKeepTheTieBreak) {
  // 50 identical triangles: no SAH split exists (equal centroids), the builder halves
  // by index, and the answer is still the lowest index from every traversal.
  std::vector<glm::vec3> tris;
  test::add_tri(tris, {-1, -1, 3}, {1, -1, 3}, {0, 1, 3});  // a farther one first
  for (int k = 0; k < 50; ++k) test::add_tri(tris, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1});
  BvhBuildStats s;
  Bvh bvh = Bvh::build(tris, &s);
  EXPECT_GE(s.leaf_count, 13u);  // <= 4 triangles per leaf
  Ray r{{0.1f, 0.0f, -1.0f}, {0.0f, 0.0f, 1.0f}};
  EXPECT_EQ(bvh.intersect1(r).prim, 1);
  RayPacket4 p;
  p.ox = float4(0.1f), p.oy = float4(0.0f), p.oz = float4(-1.0f);
  p.dx = float4(0.0f), p.dy = float4(0.0f), p.dz = float4(1.0f);
  p.tmax = float4(kInfinity);
  HitPacket4 h;
  bvh.intersect4(p, mask4(true), h);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(h.prim[i], 1);
}

TEST(Bvh, StatsDescribeTheTree) {
  std::mt19937 rng(3);
  auto tris = test::random_soup(rng, 5000, 0.05f);
  BvhBuildStats s;
  Bvh::build(tris, &s);
  // Leaves hold <= 4 triangles; a 4-wide node has 2..4 children.
  EXPECT_GE(s.leaf_count, 5000u / 4u);
  EXPECT_GE(s.node_count, (s.leaf_count - 1) / 3);
  EXPECT_LE(s.node_count, s.leaf_count);
  EXPECT_GE(s.max_depth, 10u);  // log2(5000 / 4) ~ 10.3
  EXPECT_LE(s.max_depth, size_t(kBvhMaxDepth));
  std::printf("sah_cost %.6f depth %zu leaves %zu nodes %zu build %.6f s\n", s.sah_cost, s.max_depth, s.leaf_count,
              s.node_count, s.build_seconds);
  // A uniform soup of small triangles: SAH cost a small multiple of log2(n). Measured
  // 55.2249 on this soup (mt19937 seed 3 through libstdc++'s uniform_real_distribution;
  // another standard library draws another soup); pinned to 5 %: a worse split rule (e.g.
  // median or a broken bin cost) moves it by far more.
  EXPECT_NEAR(s.sah_cost, 55.2249, 0.05 * 55.2249);
  // Something was timed, and a 5000-triangle build takes milliseconds, not seconds.
  EXPECT_GT(s.build_seconds, 0.0);
  EXPECT_LT(s.build_seconds, 5.0);
}

TEST(Bvh, SahCostOfTrivialTrees) {
  // One triangle: the root is a leaf of one, cost = 1 (its area over itself times 1).
  std::vector<glm::vec3> one;
  test::add_tri(one, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  BvhBuildStats s;
  Bvh::build(one, &s);
  EXPECT_DOUBLE_EQ(s.sah_cost, 1.0);
  EXPECT_EQ(s.max_depth, 0u);
  EXPECT_EQ(s.leaf_count, 1u);
  // Many copies of one triangle cannot be split by SAH (equal centroids and boxes): the
  // builder halves by index down to leaves of <= 4 (kMaxLeafSize), and every node has the
  // root's box, so the cost is (interior nodes) x 1 + 50 triangles. Halving 50: 25 + 25,
  // 25 -> 12 + 13, 12 -> 6 + 6 -> four 3s, 13 -> 6 + 7 -> 3, 3, 3, 4: 8 leaves per 25,
  // 16 leaves, 15 interior nodes, cost 65.
  std::vector<glm::vec3> copies;
  for (int k = 0; k < 50; ++k) test::add_tri(copies, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1});
  Bvh::build(copies, &s);
  EXPECT_DOUBLE_EQ(s.sah_cost, 65.0);
  EXPECT_EQ(s.leaf_count, 16u);
  EXPECT_EQ(s.max_depth, 4u);
}

// The collapse fills each 4-wide node with up to four children, opening interior
// children until there are four. The 50 copies' binary tree (15 interior nodes, 16
// leaves: SahCostOfTrivialTrees) collapses into 7 four-wide nodes; three-wide nodes would
// take 10.
TEST(Bvh, TheCollapseFillsFourWideNodes) {
  std::vector<glm::vec3> copies;
  for (int k = 0; k < 50; ++k) test::add_tri(copies, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1});
  BvhBuildStats s;
  Bvh::build(copies, &s);
  EXPECT_EQ(s.leaf_count, 16u);
  EXPECT_EQ(s.node_count, 7u);
}

TEST(Bvh, BuildIsDeterministic) {
  std::mt19937 rng(11);
  auto tris = test::random_soup(rng, 3000, 0.1f);
  BvhBuildStats a, b;
  Bvh x = Bvh::build(tris, &a), y = Bvh::build(tris, &b);
  EXPECT_EQ(a.node_count, b.node_count);
  EXPECT_EQ(a.sah_cost, b.sah_cost);
  for (int i = 0; i < 500; ++i) {
    Ray r = random_ray(rng);
    expect_same(x.intersect1(r), y.intersect1(r));
  }
}

TEST(Bvh, EmptyNeverHits) {
  Bvh none;
  EXPECT_TRUE(none.empty());
  Bvh built = Bvh::build({});
  EXPECT_TRUE(built.empty());
  Ray r{{0, 0, 0}, {0, 0, 1}};
  EXPECT_FALSE(built.intersect1(r).hit());
  EXPECT_FALSE(built.occluded1(r));
  RayPacket4 p{};
  p.dx = p.dy = float4(0.0f);
  p.dz = float4(1.0f);
  p.tmax = float4(kInfinity);
  HitPacket4 h;
  built.intersect4(p, mask4(true), h);
  EXPECT_EQ(h.prim[0], -1);
  EXPECT_EQ(built.occluded4(p, mask4(true)).bits(), 0);
}

TEST(Bvh, DegenerateTrianglesNeverHit) {
  std::vector<glm::vec3> tris;
  test::add_tri(tris, {0, 0, 0}, {1, 0, 0}, {2, 0, 0});  // collinear
  test::add_tri(tris, {0, 0, 0}, {0, 0, 0}, {0, 0, 0});  // a point
  test::add_tri(tris, {0, 1, 0}, {0, 1, 0}, {1, 1, 1});  // repeated vertex
  test::add_tri(tris, {0, 0, 5}, {1, 0, 5}, {0, 1, 5});  // a real one, behind them
  Bvh bvh = Bvh::build(tris);
  EXPECT_EQ(bvh.triangle_count(), 4u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  for (int i = 0; i < 1000; ++i) {
    // Rays aimed straight at points of the degenerate ones.
    glm::vec3 target = i % 2 ? glm::vec3(u(rng), 0.0f, 0.0f) : glm::vec3(0.0f);
    glm::vec3 o = target + 3.0f * test::random_unit(rng);
    Hit h = bvh.intersect1(Ray{o, target - o, 1.5f});
    EXPECT_TRUE(!h.hit() || h.prim == 3) << h.prim;
  }
  // Positive control: the same scene does report hits, on the real triangle.
  const glm::vec3 inside(0.25f, 0.25f, 5.0f);
  for (int i = 0; i < 200; ++i) {
    glm::vec3 o = inside + 3.0f * test::random_unit(rng);
    Ray r{o, inside - o, 1.5f};
    Hit h = bvh.intersect1(r);
    EXPECT_EQ(h.prim, 3);
    EXPECT_TRUE(bvh.occluded1(r));
  }
}

TEST(Bvh, NanAndZeroDirectionsNeverHit) {
  std::vector<glm::vec3> tris;
  test::add_tri(tris, {-1, -1, 1}, {1, -1, 1}, {0, 1, 1});
  Bvh bvh = Bvh::build(tris);
  float nan = std::nanf("");
  for (Ray r : {Ray{{0, 0, 0}, {nan, 0, 1}}, Ray{{0, 0, 0}, {0, 0, nan}},
                Ray{{nan, 0, 0}, {0, 0, 1}}, Ray{{0, 0, 0}, {0, 0, 0}},
                Ray{{0, 0, 0}, {0, 0, 1}, nan}, Ray{{0, 0, 0}, {kInfinity, 0, 1}}}) {
    EXPECT_FALSE(bvh.intersect1(r).hit());
    EXPECT_FALSE(bvh.occluded1(r));
  }
  EXPECT_TRUE(bvh.intersect1(Ray{{0, 0, 0}, {0, 0, 1}}).hit());  // the control
}

TEST(Bvh, NanVerticesAreDroppedNotFatal) {
  std::vector<glm::vec3> tris;
  float nan = std::nanf("");
  test::add_tri(tris, {nan, 0, 1}, {1, -1, 1}, {0, 1, 1});
  test::add_tri(tris, {-1, -1, 2}, {1, -1, 2}, {0, 1, 2});
  Bvh bvh = Bvh::build(tris);
  Hit h = bvh.intersect1(Ray{{0, 0, 0}, {0, 0, 1}});
  EXPECT_EQ(h.prim, 1);
  EXPECT_EQ(h.t, 2.0f);
}

}  // namespace
}  // namespace zz
