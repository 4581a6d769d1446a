// 4-ray packets against single rays: every lane must equal the single-ray answer bit for
// bit (closest hit and occlusion), for coherent and incoherent packets and any mask.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/bvh.h"
#include "test_meshes.h"

namespace zz {
namespace {

RayPacket4 pack(const Ray r[4]) {
  alignas(16) float f[7][4];
  for (int i = 0; i < 4; ++i) {
    f[0][i] = r[i].origin.x, f[1][i] = r[i].origin.y, f[2][i] = r[i].origin.z;
    f[3][i] = r[i].dir.x, f[4][i] = r[i].dir.y, f[5][i] = r[i].dir.z, f[6][i] = r[i].tmax;
  }
  RayPacket4 p;
  p.ox = float4::load(f[0]), p.oy = float4::load(f[1]), p.oz = float4::load(f[2]);
  p.dx = float4::load(f[3]), p.dy = float4::load(f[4]), p.dz = float4::load(f[5]);
  p.tmax = float4::load(f[6]);
  return p;
}

// Compares all four lanes; returns the number of lanes that hit.
int check_packet(const Bvh& bvh, const Ray r[4], mask4 active) {
  RayPacket4 p = pack(r);
  HitPacket4 h;
  bvh.intersect4(p, active, h);
  mask4 occ = bvh.occluded4(p, active);
  int hits = 0;
  for (int i = 0; i < 4; ++i) {
    Hit s = active[i] ? bvh.intersect1(r[i]) : Hit{};
    EXPECT_EQ(h.prim[i], s.prim) << "lane " << i;
    if (s.hit()) {
      // Bit-identical: the packet lane and the single ray share the kernel's arithmetic.
      EXPECT_EQ(h.t[i], s.t);
      EXPECT_EQ(h.u[i], s.u);
      EXPECT_EQ(h.v[i], s.v);
      ++hits;
    } else {
      EXPECT_EQ(h.t[i], kInfinity);
    }
    EXPECT_EQ(occ[i], active[i] && bvh.occluded1(r[i])) << "lane " << i;
  }
  return hits;
}

// Bvh::intersect4 / occluded4 run the packet kernel only for packets that pass this test
// (bvh_traverse4.cpp, coherent()): every active lane in one direction octant and cos > 0.8
// to the first lane. Others are traced as single rays, so comparing them with intersect1
// compares intersect1 with itself. The generators below build packets that pass it by
// design, with a margin (cos > 0.85, and |d_i| > 1e-3 so that no component's sign is in
// doubt) against rounding, and the tests assert this predicate for every packet they trace.
bool takes_packet_path(const Ray r[4]) {
  const glm::vec3 f = r[0].dir;
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 d = r[i].dir;
    for (int k = 0; k < 3; ++k)
      if (std::signbit(d[k]) != std::signbit(f[k]) || !(std::fabs(d[k]) > 1e-3f)) return false;
    if (!(glm::dot(d, f) > 0.85f * glm::length(d) * glm::length(f))) return false;
  }
  return true;
}

int dominant_axis(glm::vec3 d) {
  glm::vec3 a = glm::abs(d);
  return a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
}

class PacketTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(21);
    tris_ = test::random_soup(rng, 3000, 0.15f);
    auto s = test::uv_sphere(32, 16, 0.5f, {0.2f, 0.1f, 0.0f});
    tris_.insert(tris_.end(), s.begin(), s.end());
    bvh_ = Bvh::build(tris_);
  }
  std::vector<glm::vec3> tris_;
  Bvh bvh_;
};

TEST_F(PacketTest, CoherentPacketsMatchSingleRays) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0, packets = 0;
  for (int i = 0; i < 3000; ++i) {
    glm::vec3 o = 3.0f * test::random_unit(rng);
    glm::vec3 d = glm::normalize(-o + 0.8f * glm::vec3(u(rng), u(rng), u(rng)));
    Ray r[4];
    for (int k = 0; k < 4; ++k) {  // a 2x2 pixel footprint
      glm::vec3 dk = d + 0.002f * glm::vec3(float(k & 1), float(k >> 1), 0.0f);
      r[k] = Ray{o, dk, i % 4 == 0 ? 2.5f : kInfinity};
    }
    packets += takes_packet_path(r);  // the rest straddle an octant: lane by lane
    hits += check_packet(bvh_, r, mask4(true));
  }
  EXPECT_GT(packets, 2700);
  EXPECT_GT(hits, 3000);
}

// Directions whose two largest components tie (|dy| == |dz| > |dx|, a 45-degree view, and
// every other pair): the watertight test's shear picks its axis by those comparisons, and
// the packet's choice must break ties as the single ray's does (mutation testing: `ay >= az`
// in the packet's setup changed 11 % of such lanes by an ULP or a hit, and no test; random
// directions never tie).
TEST_F(PacketTest, TiedDirectionComponentsMatchSingleRays) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int hits = 0, packets = 0;
  for (int it = 0; it < 6000; ++it) {
    const int tied_out = it % 4;  // 0, 1, 2: that axis is the small one; 3: all three tie
    const float sign[3] = {(it >> 2) % 2 ? -1.0f : 1.0f, (it >> 3) % 2 ? -1.0f : 1.0f, (it >> 4) % 2 ? -1.0f : 1.0f};
    const float b = 1.0f + u(rng);
    Ray r[4];
    for (int k = 0; k < 4; ++k) {
      glm::vec3 d(b);
      if (tied_out < 3) d[tied_out] = b * (0.2f + 0.6f * u(rng));
      for (int a = 0; a < 3; ++a) d[a] *= sign[a];
      // From the far side of the scene's box towards its centre, so that most lanes hit.
      r[k] = Ray{-2.0f * d / b + 0.02f * glm::vec3(u(rng), u(rng), u(rng)), d, kInfinity};
    }
    packets += takes_packet_path(r);
    hits += check_packet(bvh_, r, mask4(true));
  }
  EXPECT_GT(packets, 5000);
  EXPECT_GT(hits, 3000);
}

// Axis-aligned, coplanar geometry: a floor of 64 x 64 cells in z = 0 and a copy of every
// other triangle shifted a little in x, so boxes touch and hits tie. The random soups above
// never make such boxes; dropping the packet box test's far-bound scale (kBoxFarScale) made
// 172 of 1.6 M lanes here return another (sometimes farther) hit than the single ray, and
// changed no other test (mutation testing).
TEST(PacketFlatFloor, CoplanarAxisAlignedCellsMatchSingleRays) {
  std::vector<glm::vec3> p;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const float x0 = float(i) * 0.37f - 11.0f, y0 = float(j) * 0.37f - 11.0f, x1 = x0 + 0.37f, y1 = y0 + 0.37f;
      test::add_tri(p, {x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0});
      test::add_tri(p, {x0, y0, 0}, {x1, y1, 0}, {x0, y1, 0});
      const float s = 0.013f;
      test::add_tri(p, {x0 + s, y0, 0}, {x1 + s, y0, 0}, {x1 + s, y1, 0});
    }
  const Bvh bvh = Bvh::build(p);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0, packets = 0;
  for (int it = 0; it < 100000; ++it) {
    const glm::vec3 o(u(rng) * 8, u(rng) * 8, 1.0f + 4.0f * std::abs(u(rng)));
    const glm::vec3 target(u(rng) * 10, u(rng) * 10, 0.0f);
    Ray r[4];
    for (int k = 0; k < 4; ++k) r[k] = Ray{o, target - o + 0.001f * glm::vec3(float(k & 1), float(k >> 1), 0.0f)};
    packets += takes_packet_path(r);
    hits += check_packet(bvh, r, mask4(true));
    if (::testing::Test::HasFailure()) break;  // one packet's report is enough
  }
  EXPECT_GT(packets, 90000);
  EXPECT_GT(hits, 300000);
}

// The near hits on a huge floor that only the double-precision re-test finds
// (triangle_test.cpp): packet lanes settle them with the same arithmetic as single rays.
TEST(PacketHugeTriangle, NearHitsMatchSingleRays) {
  std::vector<glm::vec3> p;
  test::add_tri(p, {-1e6f, 0, -1e6f}, {1e6f, 0, 1e6f}, {1e6f, 0, -1e6f});
  test::add_tri(p, {-1e6f, 0, -1e6f}, {-1e6f, 0, 1e6f}, {1e6f, 0, 1e6f});
  Bvh bvh = Bvh::build(p);
  std::mt19937 rng(43);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0, packets = 0, in_doubt = 0;
  for (int i = 0; i < 500; ++i) {
    // x dominant: the floor's vertices then lie at very different sheared depths, and the
    // float t's bound (which grows with them) leaves most of these hits in doubt. (With y
    // dominant they all lie at the hit's depth and the float test proves every hit.)
    const glm::vec3 o(u(rng), 0.5f + 0.3f * u(rng), u(rng));
    const glm::vec3 d(1.0f, -0.4f - 0.3f * std::abs(u(rng)), 0.1f + 0.2f * std::abs(u(rng)));
    Ray r[4];
    for (int k = 0; k < 4; ++k) r[k] = Ray{o, d + 0.01f * glm::vec3(0.0f, float(k & 1), float(k >> 1))};
    packets += takes_packet_path(r);
    hits += check_packet(bvh, r, mask4(true));
    for (const Ray& ray : r)
      if (const Hit h = bvh.intersect1(ray); h.hit()) in_doubt += test::float_test_in_doubt(p, ray, h.prim);
  }
  EXPECT_EQ(packets, 500);
  EXPECT_EQ(hits, 2000);
  EXPECT_GT(in_doubt, 1000) << "the re-test must run for this test to mean anything";
}

TEST_F(PacketTest, IncoherentPacketsMatchSingleRays) {
  // Incoherent origins (each lane its own, anywhere in the scene) and directions that are
  // just coherent enough for the packet kernel: one random octant per packet, lanes up to
  // ~30 degrees apart, so they often disagree on Woop's axis permutation and take the
  // kernel's per-lane blend path.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f), t(0.0f, 3.0f);
  int hits = 0, mixed = 0;
  for (int i = 0; i < 3000; ++i) {
    const glm::vec3 sign(rng() % 2 ? 1.0f : -1.0f, rng() % 2 ? 1.0f : -1.0f, rng() % 2 ? 1.0f : -1.0f);
    glm::vec3 base;
    do base = glm::abs(test::random_unit(rng));
    while (base.x < 0.15f || base.y < 0.15f || base.z < 0.15f);
    base *= sign;
    Ray r[4];
    for (int k = 0; k < 4; ++k) {
      glm::vec3 d;
      do d = glm::normalize(base + 0.4f * test::random_unit(rng));
      while (!(glm::dot(d, base) > 0.87f) || d.x * sign.x < 2e-3f || d.y * sign.y < 2e-3f ||
             d.z * sign.z < 2e-3f);
      if (k == 0) base = d;  // lane 0 is the reference of the coherence test
      r[k] = Ray{{u(rng), u(rng), u(rng)}, d, rng() % 2 ? t(rng) : kInfinity};
    }
    ASSERT_TRUE(takes_packet_path(r)) << "packet " << i;
    int a0 = dominant_axis(r[0].dir);
    for (int k = 1; k < 4; ++k)
      if (dominant_axis(r[k].dir) != a0) {
        ++mixed;
        break;
      }
    hits += check_packet(bvh_, r, mask4(true));
  }
  EXPECT_GT(hits, 3000);
  EXPECT_GT(mixed, 500);  // the per-lane permutation path is exercised, not just uniform
}

TEST_F(PacketTest, MixedDominantAxesInOneOctant) {
  // Same octant (the packet kernel runs), but Woop's kz differs between lanes: the
  // per-lane permutation blends must give the single-ray answers.
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(0.5f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 o = -1.3f * glm::vec3(u(rng), u(rng), u(rng));
    Ray r[4];
    glm::vec3 d0(u(rng), u(rng), u(rng));
    d0 /= std::fmax(d0.x, std::fmax(d0.y, d0.z));
    for (int k = 0; k < 4; ++k) {
      glm::vec3 d = d0;
      d[k % 3] = 1.01f;  // lane k's dominant axis; close enough to stay one packet
      r[k] = Ray{o, d};
    }
    hits += check_packet(bvh_, r, mask4(true));
  }
  EXPECT_GT(hits, 2000);
}

TEST_F(PacketTest, ActiveMaskAndBadLanes) {
  std::mt19937 rng(6);
  float nan = std::nanf("");
  for (int i = 0; i < 500; ++i) {
    Ray r[4];
    glm::vec3 o = 3.0f * test::random_unit(rng);
    for (auto& ray : r) ray = Ray{o, -o + 0.3f * test::random_unit(rng)};
    int m = int(rng() % 16);
    mask4 active((m & 1) != 0, (m & 2) != 0, (m & 4) != 0, (m & 8) != 0);
    if (i % 3 == 0) r[rng() % 4].dir.y = nan;  // a NaN lane must not disturb the others
    if (i % 5 == 0) r[rng() % 4].dir = glm::vec3(0.0f);
    check_packet(bvh_, r, active);
  }
}

// The bad directions above make the packet incoherent, so it is traced lane by lane. Bad
// lanes that keep a good direction reach the packet kernel: a NaN or infinite origin, a
// NaN, zero or negative tmax. They never hit and leave the other lanes as single rays.
TEST_F(PacketTest, BadLanesInsideThePacketKernel) {
  std::mt19937 rng(16);
  const float nan = std::nanf("");
  int packets = 0, hits = 0;
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 o = 3.0f * test::random_unit(rng);
    const glm::vec3 d = glm::normalize(-o + 0.8f * test::random_unit(rng));
    Ray r[4];
    for (int k = 0; k < 4; ++k) r[k] = Ray{o, d + 0.002f * glm::vec3(float(k & 1), float(k >> 1), 0.0f)};
    Ray& bad = r[rng() % 4];
    switch (i % 5) {
      case 0: bad.origin.x = nan; break;
      case 1: bad.origin.z = kInfinity; break;
      case 2: bad.tmax = nan; break;
      case 3: bad.tmax = 0.0f; break;
      default: bad.tmax = -1.0f; break;
    }
    packets += takes_packet_path(r);
    hits += check_packet(bvh_, r, mask4(true));
    EXPECT_FALSE(bvh_.intersect1(bad).hit());
  }
  EXPECT_GT(packets, 900);
  EXPECT_GT(hits, 1000);
}

TEST_F(PacketTest, OcclusionStopsAtTmax) {
  // Shadow packets as the shader makes them: four points close together towards one point
  // light, so the packet kernel runs (random origins all over the scene were mostly traced
  // lane by lane). Each lane's segment is cut just before and at its own first hit: the
  // packet must see the blocker at tmax = t_hit and not below it.
  std::mt19937 rng(8);
  const glm::vec3 light(0.0f, 2.5f, 0.0f);
  int blocked = 0, total = 0, packets = 0, cut = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 centre = 1.2f * test::random_unit(rng);
    Ray r[4];
    for (auto& ray : r) {
      const glm::vec3 o = centre + 0.05f * test::random_unit(rng);
      ray = Ray{o, light - o, 0.999f};
    }
    packets += takes_packet_path(r);
    check_packet(bvh_, r, mask4(true));
    for (auto& ray : r) blocked += bvh_.occluded1(ray), ++total;
    Ray before[4], at[4];
    bool any = false;
    for (int k = 0; k < 4; ++k) {
      const Hit h = bvh_.intersect1(Ray{r[k].origin, r[k].dir, kInfinity});
      before[k] = at[k] = Ray{r[k].origin, r[k].dir, 0.0f};
      if (!h.hit()) continue;
      before[k].tmax = h.t * (1.0f - 1e-4f);
      at[k].tmax = h.t;
      any = true;
    }
    if (!any) continue;
    ++cut;
    const mask4 none = bvh_.occluded4(pack(before), mask4(true)), all = bvh_.occluded4(pack(at), mask4(true));
    for (int k = 0; k < 4; ++k) {
      EXPECT_FALSE(none[k]) << "packet " << i << " lane " << k << ": blocked before its first hit";
      EXPECT_EQ(all[k], at[k].tmax > 0.0f) << "packet " << i << " lane " << k << ": not blocked at its first hit";
    }
  }
  EXPECT_GT(packets, 1500);
  EXPECT_GT(cut, 500);
  EXPECT_GT(blocked, total / 10);
  EXPECT_LT(blocked, total);
}

}  // namespace
}  // namespace zz
