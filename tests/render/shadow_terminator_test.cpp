// The shadow terminator (shader.cpp, lift_to_smooth_surface): a coarse smooth-shaded mesh
// lit from the side must look like the smooth surface its normals describe, with no
// facets or slivers left black where the shading normal faces the light.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "render/renderer.h"
#include "test_scenes.h"

namespace zz {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr int kSize = 128;
const glm::vec3 kEye{0.0f, 0.0f, 4.0f};
const glm::vec3 kToLight{1.0f, 0.0f, 0.0f};  // from the side: the terminator is the image's middle column
// Blue beyond anything the grey sphere reflects, so coverage is told apart from shadow.
const glm::vec3 kBackground{0.0f, 0.0f, 4.0f};

// The low-poly sphere lit from the side, seen from kEye.
Scene low_poly_sphere(int segments, int rings, float turn) {
  Scene s;
  s.name = "low_poly_sphere";
  s.materials.push_back(test::diffuse_material(glm::vec3(0.8f)));
  test::add_uv_sphere(s, segments, rings, turn, 0);
  Light sun;
  sun.type = Light::Type::Directional;
  sun.direction = -kToLight;
  sun.intensity = glm::vec3(kPi);  // Lambert radiance = albedo x cos
  s.lights.push_back(sun);
  s.cameras.push_back(Camera::look_at(kEye, {0, 0, 0}, {0, 1, 0}, 0.6f));
  s.max_depth = 0;
  s.background = kBackground;
  s.finalize_materials();
  return s;
}

Film render(const Scene& scene, AaMode aa, int spp) {
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  RenderSettings settings;
  settings.width = settings.height = kSize;
  settings.aa = aa;
  settings.uniform = {UniformPattern::Stratified, spp};
  Film film;
  RenderStats stats;
  render_frame(shader, scene.cameras[0], GeoMap{}, settings, film, stats);
  return film;
}

// Pixels whose centre ray sees the lit side of the ideal sphere (cos to the light >= 0.2)
// and that lie 2 pixels or more inside the mesh's silhouette in both images (the blue
// background tells where the mesh is, whatever its shading).
std::vector<bool> lit_interior(const Scene& scene, const Film& a, const Film& b) {
  const CameraRays rays(scene.cameras[0], kSize, kSize);
  std::vector<bool> mask(size_t(kSize) * kSize, false);
  auto covered = [&](int x, int y) {
    const size_t i = size_t(y) * kSize + x;
    return a.radiance[i].b < 2.0f && b.radiance[i].b < 2.0f;  // mostly sphere
  };
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 2; x < kSize - 2; ++x) {
      bool inside = true;
      for (int dy = -2; dy <= 2 && inside; ++dy)
        for (int dx = -2; dx <= 2; ++dx) inside = inside && covered(x + dx, y + dy);
      if (!inside) continue;
      const glm::vec3 d = glm::normalize(rays.direction(x + 0.5f, y + 0.5f));
      const float bq = glm::dot(kEye, d), disc = bq * bq - (glm::dot(kEye, kEye) - 1.0f);
      if (disc < 0.0f) continue;
      const glm::vec3 n = kEye + (-bq - std::sqrt(disc)) * d;
      mask[size_t(y) * kSize + x] = glm::dot(n, kToLight) >= 0.2f;
    }
  return mask;
}

// Isolated dark pixels: darker than half the median of their 8 neighbours.
int dark_speckles(const Film& f, const std::vector<bool>& mask) {
  int count = 0;
  for (int y = 1; y < kSize - 1; ++y)
    for (int x = 1; x < kSize - 1; ++x) {
      if (!mask[size_t(y) * kSize + x]) continue;
      float n[8];
      int k = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx || dy) n[k++] = f.radiance[size_t(y + dy) * kSize + x + dx].g;
      std::nth_element(n, n + 4, n + 8);
      count += f.radiance[size_t(y) * kSize + x].g < 0.5f * n[4];
    }
  return count;
}

TEST(ShadowTerminator, LowPolySphereLitSideHasNoDarkSpecklesAndMatchesTheReference) {
  for (float turn : {0.17f, 0.5f}) {
    SCOPED_TRACE(testing::Message() << "turn " << turn);
    const Scene scene = low_poly_sphere(8, 6, turn);
    const Film one = render(scene, AaMode::None, 1);
    const Film reference = render(scene, AaMode::Uniform, 256);
    const std::vector<bool> mask = lit_interior(scene, one, reference);
    const int lit = int(std::count(mask.begin(), mask.end(), true));
    ASSERT_GT(lit, 2000);  // a quarter of the sphere's disk (about 40 % of it is lit at cos >= 0.2)
    EXPECT_EQ(dark_speckles(one, mask), 0);
    // Away from the silhouette the 1-ray image is the reference: shading is smooth there,
    // so a pixel's centre sees its mean up to the curvature of the normal interpolation.
    int off = 0;
    float worst = 0.0f;
    for (size_t i = 0; i < mask.size(); ++i) {
      if (!mask[i]) continue;
      const float d = std::fabs(one.radiance[i].g - reference.radiance[i].g);
      worst = std::max(worst, d);
      off += d > 0.02f;  // albedo 0.8: 2.5 % of the brightest value
    }
    EXPECT_EQ(off, 0) << "worst difference " << worst << " over " << lit << " lit pixels";
  }
}

// What four rays straight down from z = 4 at (x, y) see in `s`.
Rgb4 trace_down(const Scene& s, float4 x, float4 y) {
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  RayPacket4 rays{};
  rays.ox = x;
  rays.oy = y;
  rays.oz = float4(4.0f);
  rays.dx = rays.dy = float4(0.0f);
  rays.dz = float4(-1.0f);
  rays.tmax = float4(kInfinity);
  RayCounters counters;
  return shader.trace4(rays, mask4(true), 0, counters);
}

TEST(ShadowTerminator, FlatMeshShadowsAreUnchanged) {
  // Flat shading (vertex normals = face normals): the lift is zero, so a box still casts
  // its hard shadow and its faces turned from the light stay dark.
  Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
  test::add_box(s, {-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, 0);
  s.finalize_materials();
  // Straight down onto the floor under the box's edge from above: one lane in the
  // shadow-free floor, three on the box top (lit).
  const Rgb4 c = trace_down(s, float4(2.0f, 0.0f, 0.2f, -0.2f), float4(2.0f, 0.0f, 0.2f, -0.2f));
  for (int i = 0; i < 4; ++i) EXPECT_GT(c.g[i], 0.0f);
  // A light low on the side: the floor behind the box is in its shadow.
  s.lights[0].position = {3.0f, 0.0f, 0.5f};
  const Rgb4 d = trace_down(s, float4(-1.0f, -1.5f, 2.0f, 0.0f), float4(0.0f));
  EXPECT_EQ(d.g[0], 0.0f);  // right behind the box
  EXPECT_EQ(d.g[1], 0.0f);
  EXPECT_GT(d.g[2], 0.0f);  // in front of it, lit
  EXPECT_EQ(d.g[3], 0.0f);  // the box top, the light below its plane
}

// A sun straight down (irradiance pi: Lambert's radiance is the albedo x cos), a camera
// above, no secondary rays; the scene's materials finalised.
void light_from_overhead(Scene& s) {
  Light sun;
  sun.type = Light::Type::Directional;
  sun.direction = {0, 0, -1};
  sun.intensity = glm::vec3(kPi);
  s.lights.push_back(sun);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.6f));
  s.max_depth = 0;
  s.finalize_materials();
}

// Concave smooth meshes keep the hit point: the lift moves shadow origins only outward
// (min(0, height)), so on a trough whose valley normal points straight up the slopes, which
// lie above the valley vertex's tangent plane, are not pushed into themselves and stay lit.
TEST(ShadowTerminator, ConcaveTroughIsNotLiftedIntoItsOwnShadow) {
  Scene s;
  s.materials.push_back(test::diffuse_material(glm::vec3(0.8f)));
  test::add_quad(s, {-2, -1, 1}, {0, -1, 0}, {0, 1, 0}, {-2, 1, 1}, 0);  // normal (1, 0, 2) / sqrt 5
  test::add_quad(s, {0, -1, 0}, {2, -1, 1}, {2, 1, 1}, {0, 1, 0}, 0);    // normal (-1, 0, 2) / sqrt 5
  for (size_t i = 0; i < s.positions.size(); ++i)
    if (s.positions[i].x == 0.0f) s.normals[i] = {0, 0, 1};  // smooth across the valley
  light_from_overhead(s);
  const Rgb4 c = trace_down(s, float4(-0.6f, -0.3f, 0.3f, 0.6f), float4(0.1f));
  // Lambert alone at the slope's own normal (cos 0.894) is a lower bound of the smooth shading.
  for (int i = 0; i < 4; ++i) EXPECT_GT(c.g[i], 0.8f * 0.89f) << i;
}

// Shadow rays leave from Hanika's lifted point p' = sum b_i (p - min(0, (p - p_i).n_i) n_i),
// vertex i's lift weighed by its own barycentric b_i. One triangle whose vertex 0 normal
// leans over it: at b = (0.6, 0.2, 0.2) the lift is 0.08 (-1, -1, 1), so the shadow ray
// starts above a sheet at z = 0.05 and passes it (weighing by another vertex's barycentric
// starts it at z = 0.027, under the sheet), but not a sheet at z = 0.1.
TEST(ShadowTerminator, TheLiftWeighsEachVertexsPlaneByItsBarycentric) {
  for (const float sheet : {0.05f, 0.1f}) {
    SCOPED_TRACE(sheet);
    Scene s;
    s.materials.push_back(test::diffuse_material(glm::vec3(0.8f)));
    test::add_triangle(s, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0);
    s.normals[0] = glm::normalize(glm::vec3(-1, -1, 1));
    test::add_quad(s, {0, 0, sheet}, {0.4f, 0, sheet}, {0.4f, 0.4f, sheet}, {0, 0.4f, sheet}, 0);
    light_from_overhead(s);
    const Bvh bvh = Bvh::build(s.positions);
    const Shader shader(s, bvh);
    // A grazing ray under the sheet onto (0.2, 0.2, 0): barycentrics (0.6, 0.2, 0.2).
    RayPacket4 rays{};
    rays.ox = float4(-1.8f);
    rays.oy = float4(0.2f);
    rays.oz = float4(0.04f);
    rays.dx = float4(1.0f);
    rays.dy = float4(0.0f);
    rays.dz = float4(-0.02f);
    rays.tmax = float4(kInfinity);
    RayCounters counters;
    const Rgb4 c = shader.trace4(rays, mask4(true, false, false, false), 0, counters);
    if (sheet < 0.08f) EXPECT_GT(c.g[0], 0.5f);
    else EXPECT_EQ(c.g[0], 0.0f);
  }
}

}  // namespace
}  // namespace zz
