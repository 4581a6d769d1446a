// Geometric hard cases for the BVH and the shader: grazing rays down to 1e-6 rad, rays
// exactly through vertices and along shared edges, coplanar overlapping triangles,
// slivers and zero-area triangles, and a 1e7 triangle beside 1e-5 ones. Single rays and
// 4-ray packets must agree bit for bit (same winner, same t), and shading stays finite.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/scene_source.h"
#include "robust_scenes.h"

namespace zz {
namespace {

using Tris = std::vector<glm::vec3>;

void tri(Tris& p, glm::vec3 a, glm::vec3 b, glm::vec3 c) { p.insert(p.end(), {a, b, c}); }

// The same ray in every lane of a packet, and each lane of a packet of 4 different rays,
// must give intersect1's answer.
void expect_packet_agrees(const Bvh& bvh, const Ray (&r)[4]) {
  RayPacket4 p;
  alignas(16) float v[7][4];
  for (int i = 0; i < 4; ++i) {
    v[0][i] = r[i].origin.x, v[1][i] = r[i].origin.y, v[2][i] = r[i].origin.z;
    v[3][i] = r[i].dir.x, v[4][i] = r[i].dir.y, v[5][i] = r[i].dir.z, v[6][i] = r[i].tmax;
  }
  p = {float4::load(v[0]), float4::load(v[1]), float4::load(v[2]), float4::load(v[3]),
       float4::load(v[4]), float4::load(v[5]), float4::load(v[6])};
  HitPacket4 h;
  bvh.intersect4(p, mask4(true), h);
  const int occluded = bvh.occluded4(p, mask4(true)).bits();
  for (int i = 0; i < 4; ++i) {
    const Hit s = bvh.intersect1(r[i]);
    ASSERT_EQ(h.prim[i], s.prim) << "lane " << i;
    if (s.hit()) {
      ASSERT_EQ(h.t[i], s.t) << "lane " << i;
      ASSERT_EQ(h.u[i], s.u);
      ASSERT_EQ(h.v[i], s.v);
      ASSERT_TRUE(std::isfinite(s.t) && std::isfinite(s.u) && std::isfinite(s.v));
    }
    ASSERT_EQ(bool((occluded >> i) & 1), s.hit()) << "lane " << i;
    ASSERT_EQ(bvh.occluded1(r[i]), s.hit());
  }
}

void expect_packet_agrees(const Bvh& bvh, const Ray& r) {
  const Ray four[4] = {r, r, r, r};
  expect_packet_agrees(bvh, four);
}

TEST(Grazing, HitsAPlaneAtAnglesDownTo1eMinus6Radians) {
  Tris p;
  tri(p, {-1e4f, -1e4f, 0}, {1e4f, -1e4f, 0}, {1e4f, 1e4f, 0});
  tri(p, {-1e4f, -1e4f, 0}, {1e4f, 1e4f, 0}, {-1e4f, 1e4f, 0});
  const Bvh bvh = Bvh::build(p);
  double worst = 0.0;
  for (double angle : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    // Starts above the plane, dips into it 10 units further (plus a y offset so the ray
    // does not run along the quad's diagonal edge).
    const double h = 10.0 * std::tan(angle);
    const Ray r{{0.0f, 0.3f, float(h)}, {float(std::cos(angle)), 0.0f, float(-std::sin(angle))}};
    const Hit hit = bvh.intersect1(r);
    ASSERT_TRUE(hit.hit()) << angle;
    const double expected = h / std::sin(angle);
    const double rel = std::abs(double(hit.t) - expected) / expected;
    worst = std::max(worst, rel);
    EXPECT_LT(rel, 1e-3) << angle;  // t = h / sin(angle) to float accuracy of h and angle
    expect_packet_agrees(bvh, r);
    // Parallel just above, and grazing away from the plane: no hit.
    EXPECT_FALSE(bvh.intersect1(Ray{{0.0f, 0.3f, float(h)}, {1.0f, 0.0f, 0.0f}}).hit());
    EXPECT_FALSE(bvh.intersect1(Ray{{0.0f, 0.3f, float(h)}, {float(std::cos(angle)), 0.0f, float(std::sin(angle))}}).hit());
  }
  std::printf("[ grazing ] worst relative t error down to 1e-6 rad: %.3g\n", worst);
}

TEST(Grazing, LightAt1eMinus6RadiansLightsTheFloorWithoutAcne) {
  // Light 10 units away, 1e-5 above the floor: cos = 1e-6. Lambert: L = I cos / d^2 * rho / pi.
  for (double angle : {1e-2, 1e-4, 1e-6}) {
    Scene s = test::lit_floor(0.5f, 1.0f, 3.0f);
    s.materials[0].roughness = 1.0f;
    const float d = 10.0f;
    s.lights[0].position = {d * float(std::cos(angle)), 0.0f, d * float(std::sin(angle))};
    s.lights[0].intensity = glm::vec3(100.0f);
    s.finalize_materials();
    const Bvh bvh = Bvh::build(s.positions);
    const Shader shader(s, bvh);
    const CameraRays rays(s.cameras[0], 9, 9);
    SceneSource source(shader, rays);
    // The four pixels around the centre (all within 0.2 units of the point under the camera).
    const Rgb4 c = source.sample4(float4(4.3f, 4.7f, 4.3f, 4.7f), float4(4.3f, 4.3f, 4.7f, 4.7f));
    for (int i = 0; i < 4; ++i) {
      const double lambert = 100.0 * std::sin(angle) / (d * d) * 0.5 / 3.14159265358979;
      ASSERT_TRUE(std::isfinite(c.r[i]));
      // Lit (no acne) and close to Lambert (the Phong term adds <= 3/(2 pi) * 0.04 of it;
      // the point moves by < 0.2 units, i.e. < 4 % of cos at this distance).
      EXPECT_GT(c.r[i], 0.9 * lambert) << angle;
      EXPECT_LT(c.r[i], 1.2 * lambert) << angle;
    }
  }
}

TEST(Edges, RaysThroughEveryVertexAndEdgeOfAGridHit) {
  // A 10x10 grid of quads split into triangles, vertices on a bumpy height field so that
  // neighbouring triangles are not coplanar. Rays straight down and oblique through every
  // vertex and every edge midpoint must hit (watertight), packet == single.
  const int n = 10;
  auto z = [](int i, int j) { return 0.1f * float((i * 7 + j * 3) % 5); };
  auto v = [&](int i, int j) { return glm::vec3(float(i), float(j), z(i, j)); };
  Tris p;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tri(p, v(i, j), v(i + 1, j), v(i + 1, j + 1));
      tri(p, v(i, j), v(i + 1, j + 1), v(i, j + 1));
    }
  const Bvh bvh = Bvh::build(p);
  int rays = 0, misses = 0;
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) {
      const glm::vec3 targets[4] = {v(i, j), 0.5f * (v(i, j) + v(i + 1, j)), 0.5f * (v(i, j) + v(i, j + 1)),
                                    0.5f * (v(i, j) + v(i + 1, j + 1))};
      for (glm::vec3 dir : {glm::vec3(0, 0, -1), glm::vec3(0.3f, -0.2f, -1.0f), glm::vec3(-0.7f, 0.6f, -0.5f)}) {
        Ray four[4];
        for (int k = 0; k < 4; ++k) {
          four[k] = Ray{targets[k] - 3.0f * dir, dir};
          ++rays;
          misses += !bvh.intersect1(four[k]).hit();
        }
        expect_packet_agrees(bvh, four);
      }
    }
  std::printf("[ edges ] %d rays through vertices/edges, %d misses\n", rays, misses);
  EXPECT_EQ(misses, 0);
  // A ray lying in a triangle's plane exactly along a shared edge: a degenerate
  // projection, never a hit and never a NaN.
  Tris flat;
  tri(flat, {0, 0, 0}, {1, 0, 0}, {1, 1, 0});
  tri(flat, {0, 0, 0}, {1, 1, 0}, {0, 1, 0});
  const Bvh fb = Bvh::build(flat);
  const Ray along{{-1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}};
  EXPECT_FALSE(fb.intersect1(along).hit());
  expect_packet_agrees(fb, along);
}

TEST(Coplanar, OverlappingTrianglesHaveADeterministicWinner) {
  // Triangles 0 and 2 overlap triangle 1 in the same plane; 3 duplicates 1 exactly.
  Tris p;
  tri(p, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
  tri(p, {-0.5f, -1, 0}, {1.5f, -1, 0}, {0.5f, 1, 0});
  tri(p, {-1, -0.5f, 0}, {1, -0.5f, 0}, {0, 1.5f, 0});
  tri(p, {-0.5f, -1, 0}, {1.5f, -1, 0}, {0.5f, 1, 0});
  const Bvh bvh = Bvh::build(p);
  int counts[4] = {};
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; i += 4) {
      Ray four[4];
      for (int k = 0; k < 4; ++k) {
        const float x = -1.0f + 2.5f * float(i + k) / 40.0f, y = -1.0f + 2.5f * float(j) / 40.0f;
        four[k] = Ray{{x, y, 2.0f}, {0.05f * float(k), 0.0f, -1.0f}};
        const Hit h = bvh.intersect1(four[k]);
        if (h.hit()) {
          ++counts[h.prim];
          // Equal t: the lowest index among the triangles containing the point wins.
          ASSERT_NE(h.prim, 3) << "the duplicate of triangle 1 must never win";
        }
      }
      expect_packet_agrees(bvh, four);
    }
  std::printf("[ coplanar ] winners: tri0 %d, tri1 %d, tri2 %d, tri3 %d\n", counts[0], counts[1], counts[2], counts[3]);
  EXPECT_GT(counts[0], 0);
  EXPECT_GT(counts[1], 0);
  EXPECT_GT(counts[2], 0);

  // Rendered: two coplanar quads of different colours; the image does not depend on
  // thread count or tile size, and the lower index wins everywhere they overlap.
  Scene s;
  s.materials.push_back(test::diffuse_material({0, 0, 0}));
  s.materials.push_back(test::diffuse_material({0, 0, 0}));
  s.materials[0].emissive = {1, 0, 0};
  s.materials[1].emissive = {0, 1, 0};
  test::add_quad(s, {-2, -2, 0}, {1, -2, 0}, {1, 2, 0}, {-2, 2, 0}, 0);
  test::add_quad(s, {-1, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-1, 2, 0}, 1);
  s.cameras.push_back(Camera::look_at({0.3f, 0.2f, 3}, {0, 0, 0}, {0, 1, 0}, 1.0f));
  s.max_depth = 0;
  s.finalize_materials();
  for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
    RenderSettings rs = robust::settings(67, 45, aa, 1);
    const Film a = robust::render(s, rs);
    rs.threads = 2;
    rs.tile_size = 16;
    const Film b = robust::render(s, rs);
    EXPECT_TRUE(robust::bit_identical(a, b));
    // Pixel centres over the overlap [-1, 1] x [-2, 2] are red.
    const Film c = robust::render(s, robust::settings(67, 45, AaMode::None));
    const glm::vec3 mid = c.radiance[size_t(22) * 67 + 33];
    EXPECT_EQ(mid, glm::vec3(1, 0, 0));
  }
}

TEST(Degenerate, SliversAndZeroAreaTrianglesNeverBreakTracing) {
  Tris p;
  tri(p, {0, 0, 0}, {1, 0, 0}, {2, 0, 0});             // collinear
  tri(p, {0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}, {0.5f, 0.5f, 0});  // a point
  tri(p, {0, 0, 0}, {1, 0, 0}, {1, 0, 0});             // two equal vertices
  tri(p, {0, 1, 0}, {1, 1, 0}, {0.5f, 1.0f + 1e-7f, 0});  // sliver, 1e-7 wide
  tri(p, {0, 2, 0}, {1e-7f, 2, 0}, {0, 3, 0});           // needle
  const Bvh bvh = Bvh::build(p);
  int hits_on_degenerate = 0;
  for (int j = 0; j <= 300; ++j)
    for (int i = 0; i <= 20; i += 4) {
      Ray four[4];
      for (int k = 0; k < 4; ++k) {
        four[k] = Ray{{-0.2f + 0.07f * float(i + k), -0.1f + 0.01f * float(j), 1.0f}, {0.0f, 1e-4f * float(k), -1.0f}};
        const Hit h = bvh.intersect1(four[k]);
        hits_on_degenerate += h.hit() && h.prim < 3;
      }
      expect_packet_agrees(bvh, four);
    }
  EXPECT_EQ(hits_on_degenerate, 0);
  // Exactly through the sliver's apex and along the line of the collinear triangle.
  expect_packet_agrees(bvh, Ray{{0.5f, 1.0f + 1e-7f, 1.0f}, {0, 0, -1}});
  expect_packet_agrees(bvh, Ray{{1.0f, 0.0f, 1.0f}, {0, 0, -1}});

  // A fan of 200 slivers shaded and rendered: finite and non-negative everywhere.
  Scene s = test::lit_floor(0.5f, 50.0f, 3.0f);
  for (int k = 0; k < 200; ++k) {
    const float a = 6.2831853f * float(k) / 200.0f, b = a + 1e-6f;
    const glm::vec3 c{0, 0, 0.5f}, e1{2 * std::cos(a), 2 * std::sin(a), 0.5f}, e2{2 * std::cos(b), 2 * std::sin(b), 0.5f};
    const glm::vec3 n = glm::cross(e1 - c, e2 - c);
    if (glm::dot(n, n) > 0.0f) test::add_triangle(s, c, e1, e2, 0);
  }
  s.finalize_materials();
  for (AaMode aa : {AaMode::None, AaMode::Adaptive}) EXPECT_EQ(robust::bad_values(robust::render(s, robust::settings(48, 48, aa))), 0u);
}

TEST(Extremes, TinyTrianglesBesideAHugeOne) {
  // A 1e7 floor triangle and 1e-5 triangles 1e-4 above it at the origin and at x = 1
  // (where 1e-5 is still ~80 float steps; at x = 1e4 it would round to a point).
  Tris p;
  tri(p, {-1e7f, -1e7f, 0}, {1e7f, -1e7f, 0}, {0, 1e7f, 0});
  tri(p, {-1e-5f, -1e-5f, 1e-4f}, {1e-5f, -1e-5f, 1e-4f}, {0, 1e-5f, 1e-4f});
  tri(p, {1.0f - 1e-5f, -1e-5f, 1e-4f}, {1.0f + 1e-5f, -1e-5f, 1e-4f}, {1.0f, 1e-5f, 1e-4f});
  const Bvh bvh = Bvh::build(p);
  for (float x0 : {0.0f, 1.0f}) {
    const int tiny = x0 == 0.0f ? 1 : 2;
    const Ray onto{{x0, 0.0f, 1.0f}, {0, 0, -1}};
    const Hit h = bvh.intersect1(onto);
    ASSERT_EQ(h.prim, tiny) << x0;
    EXPECT_NEAR(h.t, 1.0f - 1e-4f, 1e-6f);
    expect_packet_agrees(bvh, onto);
    const Ray beside{{x0 + 3e-5f, 0.0f, 1.0f}, {0, 0, -1}};
    const Hit f = bvh.intersect1(beside);
    ASSERT_EQ(f.prim, 0) << x0;
    EXPECT_EQ(f.t, 1.0f);
    expect_packet_agrees(bvh, beside);
  }

  // Rendered from 1e-3 above: the tiny triangle, its shadow and the lit floor, no acne.
  Scene s;
  s.materials.push_back(test::diffuse_material(glm::vec3(0.6f)));
  test::add_triangle(s, {-1e7f, -1e7f, 0}, {1e7f, -1e7f, 0}, {0, 1e7f, 0}, 0);
  test::add_triangle(s, {-1e-5f, -1e-5f, 1e-4f}, {1e-5f, -1e-5f, 1e-4f}, {0, 1e-5f, 1e-4f}, 0);
  Light l;
  l.position = {1e-4f, 0.0f, 1e-3f};
  l.intensity = glm::vec3(1e-6f);
  s.lights.push_back(l);
  s.cameras.push_back(Camera::look_at({0, 0, 1e-3f}, {0, 0, 0}, {0, 1, 0}, 0.2f));
  s.max_depth = 0;
  s.finalize_materials();
  const Film film = robust::render(s, robust::settings(64, 64, AaMode::None));
  ASSERT_EQ(robust::bad_values(film), 0u);
  int black = 0;
  for (const glm::vec3& c : film.radiance) black += c.r <= 0.0f;
  // The tiny triangle covers ~7 % of the view and its shadow a little more; black pixels
  // beyond that would be acne.
  std::printf("[ extremes ] black pixels on the 1e7 floor beside the 1e-5 triangle: %d of %d\n", black, 64 * 64);
  EXPECT_LT(black, 64 * 64 / 5);
}

TEST(Extremes, DenormalCoordinatesBuildAndTrace) {
  // Parallel triangles at x = k * 1e-41 (denormal): the centroids' extent along x is
  // denormal, so a SAH bin scale of bins / extent overflows to +Inf (and 0 * Inf = NaN)
  // unless the builder guards it. Found by fuzz_gltf (tools/fuzz/regressions/gltf/
  // bvh_build_segv_glass.gltf: bufferViews reinterpreted as floats give denormals).
  Tris p;
  for (int k = 0; k < 16; ++k) {
    const float d = float(k) * 1e-41f;
    tri(p, {d, -1, -1}, {d, 1, -1}, {d, 0, 1});
  }
  const Bvh bvh = Bvh::build(p);
  const Ray r{{1.0f, 0.0f, 0.0f}, {-1.0f, 0.0f, 0.0f}};
  const Hit h = bvh.intersect1(r);
  ASSERT_TRUE(h.hit());
  // 1 - k * 1e-41 rounds to 1 for every k: all 16 hits have the same t, and equal t goes
  // to the lowest triangle index (the documented tie-break).
  EXPECT_EQ(h.t, 1.0f);
  EXPECT_EQ(h.prim, 0);
  expect_packet_agrees(bvh, r);
}

}  // namespace
}  // namespace zz
