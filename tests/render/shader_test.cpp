#include "render/shader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/scene_source.h"
#include "render/see_through.h"
#include "test_scenes.h"

namespace zz {
namespace {

constexpr float kPi = 3.14159265358979f;

// Radiance through the centre of a 9x9 frame (pixel 4,4 centre = point (4.5, 4.5)).
glm::vec3 centre_radiance(const Scene& scene, RayCounters* counters = nullptr) {
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const CameraRays rays(scene.cameras[0], 9, 9);
  SceneSource source(shader, rays);
  const Rgb4 c = source.sample4(float4(4.5f), float4(4.5f));
  if (counters) *counters = source.counters;
  return {c.r[0], c.g[0], c.b[0]};
}

TEST(Shader, LitPlaneMatchesTheRadianceEquation) {
  // L = I cos / d^2 * (rho / pi + F0 (n + 2) / (2 pi) cos_r^n), light and eye straight above:
  // cos = cos_r = 1; roughness 1 gives the Phong exponent 1 and F0 = 0.04.
  const float albedo = 0.5f, intensity = 100.0f, height = 3.0f;
  const glm::vec3 l = centre_radiance(test::lit_floor(albedo, intensity, height));
  const float expected = intensity / (height * height) * (albedo / kPi + 0.04f * 3.0f / (2.0f * kPi));
  EXPECT_NEAR(l.r, expected, expected * 1e-4f);
  EXPECT_EQ(l.r, l.g);
  EXPECT_EQ(l.r, l.b);
}

TEST(Shader, LitPlaneFollowsInverseSquareLaw) {
  const glm::vec3 near = centre_radiance(test::lit_floor(0.8f, 50.0f, 2.0f));
  const glm::vec3 far = centre_radiance(test::lit_floor(0.8f, 50.0f, 4.0f));
  EXPECT_NEAR(near.r / far.r, 4.0f, 4e-4f);
}

TEST(Shader, OccluderCastsAHardShadow) {
  Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
  // A small square between the light and the floor point under the camera... but seen
  // edge-on from the camera it would hide the floor, so put it off the camera ray: the
  // light sits to the side.
  s.lights[0].position = {2.0f, 0.0f, 3.0f};
  test::add_quad(s, {0.9f, -0.2f, 1.4f}, {1.1f, -0.2f, 1.4f}, {1.1f, 0.2f, 1.4f}, {0.9f, 0.2f, 1.4f}, 0);
  s.finalize_materials();
  RayCounters counters;
  const glm::vec3 l = centre_radiance(s, &counters);
  EXPECT_EQ(l.r, 0.0f);
  EXPECT_EQ(counters.shadow, 4u);
}

// A light set on a surface (a lamp on the ceiling) lights the room: the surface meets its
// shadow segments at t = 1 up to rounding, which shadowed most of the floor.
TEST(Shader, ALightOnASurfaceIsNotShadowedByIt) {
  for (int k = 0; k < 16; ++k) {
    SCOPED_TRACE(k);
    Scene open = test::lit_floor(0.5f, 100.0f, 3.0f);
    open.cameras[0] = Camera::look_at({0, 0, 2.5f}, {0, 0, 0}, {0, 1, 0}, 0.5f);
    open.lights[0].position = {0.1234f + 0.0711f * float(k), 0.377f - 0.0529f * float(k), 3.0f};
    Scene ceiling = open;
    test::add_quad(ceiling, {-10, -10, 3}, {-10, 10, 3}, {10, 10, 3}, {10, -10, 3}, 0);  // facing down
    ceiling.finalize_materials();
    const glm::vec3 lit = centre_radiance(open), under = centre_radiance(ceiling);
    ASSERT_GT(lit.r, 0.0f);
    EXPECT_EQ(under.r, lit.r);
  }
}

TEST(Shader, NoLightsMeansNoShadowRays) {
  Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
  s.lights.clear();
  RayCounters counters;
  const glm::vec3 l = centre_radiance(s, &counters);
  EXPECT_EQ(l.r, 0.0f);
  EXPECT_EQ(counters.shadow, 0u);
  EXPECT_EQ(counters.reflection, 0u);
  EXPECT_EQ(counters.refraction, 0u);
  EXPECT_EQ(counters.primary, 4u);
}

TEST(Shader, MissReturnsBackground) {
  Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
  s.background = {0.1f, 0.2f, 0.3f};
  s.cameras[0] = Camera::look_at({0, 0, 4}, {0, 0, 10}, {0, 1, 0}, 0.5f);
  const glm::vec3 l = centre_radiance(s);
  EXPECT_EQ(l, glm::vec3(0.1f, 0.2f, 0.3f));
}

TEST(Shader, MirrorReflectsTheBackgroundAtF0) {
  // A perfect metal mirror (F0 = base colour) reflecting the background straight back.
  Scene s;
  s.materials.push_back(test::mirror_material(glm::vec3(0.9f, 0.5f, 0.2f)));
  test::add_quad(s, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.background = glm::vec3(1.0f);
  s.max_depth = 2;
  s.finalize_materials();
  RayCounters counters;
  const glm::vec3 l = centre_radiance(s, &counters);
  EXPECT_NEAR(l.r, 0.9f, 1e-6f);
  EXPECT_NEAR(l.g, 0.5f, 1e-6f);
  EXPECT_NEAR(l.b, 0.2f, 1e-6f);
  EXPECT_EQ(counters.reflection, 4u);
  EXPECT_EQ(counters.refraction, 0u);
}

TEST(Shader, TraceDepthZeroSpawnsNoSecondaryRays) {
  Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
  s.materials[0].metallic = 1.0f;
  s.materials[0].roughness = 0.0f;
  s.max_depth = 0;
  s.finalize_materials();
  RayCounters counters;
  centre_radiance(s, &counters);
  EXPECT_EQ(counters.reflection, 0u);
}

TEST(Shader, GlassOfIorOneVanishes) {
  Scene plain = test::lit_floor(0.5f, 100.0f, 3.0f);
  plain.lights[0].position = {0.5f, 0.3f, 3.0f};
  Scene with_glass = plain;
  with_glass.materials.push_back(test::glass_material(1.0f));
  test::add_box(with_glass, {-1, -1, 0.5f}, {1, 1, 1.5f}, 1);
  with_glass.max_depth = 2;  // in through the top, out through the bottom, then the floor
  with_glass.finalize_materials();
  plain.finalize_materials();
  // Shadow rays see the box as an occluder (hard shadows), so light from the side of the
  // box is compared against the plain floor lit by nothing: use primary+refraction only.
  with_glass.lights.clear();
  plain.lights.clear();
  plain.background = with_glass.background = glm::vec3(0.0f);
  with_glass.materials[0].emissive = plain.materials[0].emissive = glm::vec3(0.25f, 0.5f, 0.75f);
  with_glass.finalize_materials();
  plain.finalize_materials();
  RayCounters counters;
  const glm::vec3 a = centre_radiance(plain);
  const glm::vec3 b = centre_radiance(with_glass, &counters);
  EXPECT_NEAR(b.r, a.r, 1e-6f);
  EXPECT_NEAR(b.g, a.g, 1e-6f);
  EXPECT_NEAR(b.b, a.b, 1e-6f);
  EXPECT_GE(counters.refraction, 8u);  // into and out of the box
}

// Nested volumes: a ray inside a tinted glass that meets an object there crossed the
// glass (Beer-Lambert was applied only where a ray left a volume through its back face, so
// a light inside the glass shone untinted); and an interface between two media of one
// index is no interface (the index ratio was taken against air on the outside).
// A black surface that emits 1: what the tests below see through glass.
Material glow_material() {
  Material glow;
  glow.base_color = glm::vec3(0.0f);
  glow.emissive = glm::vec3(1.0f);
  return glow;
}

// Glass that absorbs red: sigma_r = -ln(0.05) / distance per unit, green and blue pass.
Material red_absorbing_glass(float distance) {
  Material tinted = test::glass_material(1.5f);
  tinted.attenuation_color = glm::vec3(0.05f, 1.0f, 1.0f);
  tinted.attenuation_distance = distance;
  return tinted;
}

Scene glass_block_around(const Material& inner, glm::vec3 camera) {
  Scene s;
  s.name = "nested";
  s.materials.push_back(glow_material());
  s.materials.push_back(red_absorbing_glass(0.5f));
  s.materials.push_back(inner);
  test::add_quad(s, {-20, -20, -3}, {20, -20, -3}, {20, 20, -3}, {-20, 20, -3}, 0);  // a glowing wall behind
  test::add_box(s, {-1, -1, -1}, {1, 1, 1}, 1);
  test::add_box(s, {-0.2f, -0.2f, -0.2f}, {0.2f, 0.2f, 0.2f}, 2);
  s.cameras.push_back(Camera::look_at(camera, {0, 0, 0}, {0, 1, 0}, 0.3f));
  s.background = glm::vec3(0.0f);
  s.max_depth = 16;  // the inner cube's faces take bounces too: both scenes' paths end on their weight
  s.finalize_materials();
  return s;
}

// glass_block_around's scene with the inner cube's triangles dropped (its material kept).
Scene glass_block_without_its_inner_cube() {
  Material empty = test::glass_material(1.5f);
  empty.transmission = 0.0f;
  Scene s = glass_block_around(empty, {0, 0, 5});
  s.positions.resize(s.positions.size() - 36);
  s.normals.resize(s.normals.size() - 36);
  s.uvs.resize(s.uvs.size() - 36);
  s.material_of.resize(s.material_of.size() - 12);
  return s;
}

TEST(Shader, AbsorptionTintsWhatLiesInsideAVolume) {
  // Straight in: through 0.8 units of the tinted glass to the glowing cube inside it.
  const glm::vec3 l = centre_radiance(glass_block_around(glow_material(), {0, 0, 5}));
  const float sigma = -std::log(0.05f) / 0.5f;
  ASSERT_GT(l.g, 0.5f);
  EXPECT_NEAR(l.r / l.g, std::exp(-sigma * 0.8f), 1e-4f);
  EXPECT_EQ(l.g, l.b);
}

// A volume's surface that is open (a pane modelled as one sheet of tinted glass, or the
// see-through share of a BLEND volume) leaves the ray in air behind it: what lies behind is
// not tinted by its distance from the pane.
TEST(Shader, AnOpenVolumeSurfaceTintsNothingBehindIt) {
  for (const bool blend : {false, true}) {
    glm::vec3 seen[2];
    for (int k = 0; k < 2; ++k) {
      const float wall = k == 0 ? -2.0f : -20.0f;
      Scene s;
      s.name = "pane";
      s.materials.push_back(glow_material());
      Material tinted = red_absorbing_glass(10.0f);
      if (blend) {
        tinted.alpha_mode = AlphaMode::Blend;
        tinted.base_alpha = 0.5f;
      }
      s.materials.push_back(tinted);
      test::add_quad(s, {-200, -200, wall}, {200, -200, wall}, {200, 200, wall}, {-200, 200, wall}, 0);
      test::add_quad(s, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, 1);  // one sheet, facing the camera
      s.cameras.push_back(Camera::look_at({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 0.3f));
      s.background = glm::vec3(0.0f);
      s.max_depth = 4;
      s.finalize_materials();
      seen[k] = centre_radiance(s);
    }
    SCOPED_TRACE(blend);
    ASSERT_GT(seen[0].g, 0.5f);
    EXPECT_NEAR(seen[1].r, seen[0].r, 1e-6f);
    EXPECT_NEAR(seen[1].g, seen[0].g, 1e-6f);
  }
}

TEST(Shader, AnInterfaceBetweenMediaOfOneIndexIsNone) {
  const Material same = red_absorbing_glass(0.5f);  // the outer glass's medium too
  Material empty = test::glass_material(1.5f);  // a cube of the outer glass: no inner object
  empty.transmission = 0.0f;
  for (const glm::vec3 camera : {glm::vec3(0, 0, 5), glm::vec3(1.5f, 0.7f, 4.5f)}) {
    SCOPED_TRACE(camera.x);
    Scene without = glass_block_around(empty, camera);
    without.positions.resize(without.positions.size() - 36);  // drop the inner cube
    without.normals.resize(without.normals.size() - 36);
    without.uvs.resize(without.uvs.size() - 36);
    without.material_of.resize(without.material_of.size() - 12);
    RayCounters counters;
    const glm::vec3 a = centre_radiance(without), b = centre_radiance(glass_block_around(same, camera), &counters);
    ASSERT_GT(a.g, 0.1f);
    EXPECT_NEAR(b.r, a.r, 1e-5f * a.g);
    EXPECT_NEAR(b.g, a.g, 1e-5f * a.g);
    EXPECT_GE(counters.refraction, 16u);  // the inner cube's two faces were crossed
  }
}

// Hit points on a volume's own faces count as inside its bounds, however the barycentric
// interpolation rounds them (a margin of a few ULPs): a ray leaving an inner cube of the
// outer glass's medium through any point of its faces goes on in the outer glass, so
// the inner cube stays invisible for rays through all of it, not only the centre's.
TEST(Shader, AVolumesOwnFacesCountAsInsideItsBoundsEverywhere) {
  Scene without = glass_block_without_its_inner_cube();
  const Scene with = glass_block_around(red_absorbing_glass(0.5f), {0, 0, 5});
  auto trace = [](const Scene& s, float4 x, float4 y) {
    const Bvh bvh = Bvh::build(s.positions);
    const Shader shader(s, bvh);
    const CameraRays rays(s.cameras[0], 9, 9);
    SceneSource source(shader, rays);
    return source.sample4(x, y);
  };
  for (int row = 0; row < 6; ++row) {
    const float4 x(3.3f, 3.9f, 4.6f, 5.3f), y(3.4f + 0.43f * float(row));
    const Rgb4 a = trace(without, x, y), b = trace(with, x, y);
    for (int i = 0; i < 4; ++i) {
      SCOPED_TRACE(testing::Message() << "row " << row << " lane " << i);
      ASSERT_GT(a.g[i], 0.1f);
      EXPECT_NEAR(b.r[i], a.r[i], 1e-5f * a.g[i]);
      EXPECT_NEAR(b.g[i], a.g[i], 1e-5f * a.g[i]);
    }
  }
}

// Where the shading normal's mirror direction points below the surface (a normal leaning
// far from the geometric one at a grazing view), the ray reflects about the geometric
// normal: a metal mirror shows the sky at F0, not its own surface.
TEST(Shader, AMirrorDirectionBelowTheSurfaceReflectsAboutTheGeometricNormal) {
  Scene s;
  s.materials.push_back(test::mirror_material(glm::vec3(0.9f)));
  test::add_quad(s, {-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}, 0);
  for (glm::vec3& n : s.normals) n = glm::normalize(glm::vec3(-0.4f, 0.0f, 0.9165f));
  // wo = (0.866, 0, 0.5): ns . wo = 0.11 > 0, but 2 (ns . wo) ns - wo points down.
  s.cameras.push_back(Camera::look_at({std::sqrt(3.0f), 0, 1}, {0, 0, 0}, {0, 0, 1}, 0.3f));
  s.background = glm::vec3(1.0f);
  s.max_depth = 2;
  s.finalize_materials();
  const glm::vec3 l = centre_radiance(s);
  EXPECT_NEAR(l.r, 0.9f, 1e-5f);
}

// A reflection whose path keeps less than kMinThroughput (1/1024) of the light is not traced.
TEST(Shader, AMirrorWeakerThanTheThroughputCutoffSpawnsNoReflection) {
  for (const float f0 : {0.9f / 1024.0f, 1.1f / 1024.0f}) {
    SCOPED_TRACE(f0);
    Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
    s.materials[0] = test::mirror_material(glm::vec3(f0));
    s.finalize_materials();
    RayCounters counters;
    centre_radiance(s, &counters);
    EXPECT_EQ(counters.reflection, f0 >= Shader::kMinThroughput ? 4u : 0u);
  }
}

// A ray inside a volume that meets the back face of another volume it never entered (an
// open sheet of it) stays in the medium it is in: with the same index that sheet is no
// interface, and what lies behind is seen as without it.
TEST(Shader, ABackFaceOfAVolumeNotEnteredLeavesTheRayInItsMedium) {
  Scene without = glass_block_without_its_inner_cube();
  without.finalize_materials();
  Scene with = without;
  with.materials[2] = red_absorbing_glass(0.5f);  // the outer glass's medium, a volume of its own
  test::add_quad(with, {-0.5f, -0.5f, 0.3f}, {-0.5f, 0.5f, 0.3f}, {0.5f, 0.5f, 0.3f}, {0.5f, -0.5f, 0.3f}, 2);  // facing -z
  with.finalize_materials();
  const glm::vec3 a = centre_radiance(without), b = centre_radiance(with);
  ASSERT_GT(a.g, 0.1f);
  // Within 1e-3: light reflected inside the glass that comes back up through the sheet is
  // taken as inside the sheet's volume (6e-5 of the total); an interface of index 1.5 would
  // reflect 4 % of the light here.
  EXPECT_NEAR(b.r, a.r, 1e-3f * a.g);
  EXPECT_NEAR(b.g, a.g, 1e-3f * a.g);
}

TEST(Fresnel, NormalIncidence) {
  // ((n1 - n2) / (n1 + n2))^2 = 0.04 for air/glass 1.5, either direction.
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  EXPECT_EQ(fresnel_dielectric(1.0f, 1.0f), 0.0f);
}

// An interface of index ratio 1 is no interface, at any angle: below cos_i ~2.4e-4,
// 1 - eta^2 (1 - cos^2_i) rounded to 0 and it reflected everything. Nor does light
// entering a denser medium ever reflect totally.
TEST(Fresnel, NoInterfaceAtRatioOneAndNoTotalReflectionIntoADenserMedium) {
  for (const float c : {1e-7f, 1e-5f, 1e-4f, 2e-4f, 3e-4f, 1e-3f, 0.3f, 1.0f}) {
    SCOPED_TRACE(c);
    EXPECT_EQ(fresnel_dielectric(c, 1.0f), 0.0f);
    EXPECT_EQ(cos_transmitted(c, 1.0f), c);
    EXPECT_LT(fresnel_dielectric(c, 1.0f / 1.0001f), 1.0f);
    EXPECT_GE(cos_transmitted(c, 1.0f / 1.5f), 0.0f);
  }
  EXPECT_EQ(cos_transmitted(0.1f, 1.5f), -1.0f);  // beyond glass -> air's critical angle
}

// Total internal reflection needs a denser medium behind (eta > 1): at ratio 1 a ray at
// exactly grazing incidence (cos_i = 0, or a cos_i whose square underflows) goes on at
// cos_t = 0, not reflected.
TEST(Fresnel, NoTotalReflectionAtRatioOneEvenAtGrazing) {
  for (const float c : {0.0f, 1e-30f}) {
    SCOPED_TRACE(c);
    EXPECT_EQ(cos_transmitted(c, 1.0f), 0.0f);
  }
}

// Index ratio 1 is no interface at exactly grazing incidence too: Fresnel's terms there
// are 0 / 0 (cos_i = cos_t = 0, or a cos_i whose square underflows), which gave NaN, and a
// NaN reflectance dropped both the reflection and the refraction of the ray.
TEST(Fresnel, NoReflectionAtRatioOneEvenAtGrazing) {
  for (const float c : {0.0f, 1e-30f}) {
    SCOPED_TRACE(c);
    EXPECT_EQ(fresnel_dielectric(c, 1.0f), 0.0f);
  }
}

TEST(Fresnel, TotalInternalReflectionBeyondTheCriticalAngle) {
  const float eta = 1.5f;  // glass -> air
  const float critical = std::asin(1.0f / eta);
  EXPECT_EQ(fresnel_dielectric(std::cos(critical + 1e-3f), eta), 1.0f);
  EXPECT_EQ(fresnel_dielectric(std::cos(1.5f), eta), 1.0f);
  EXPECT_LT(fresnel_dielectric(std::cos(critical - 1e-2f), eta), 1.0f);
  EXPECT_EQ(fresnel_dielectric(0.0f, 1.0f / eta), 1.0f);  // grazing from outside
}

TEST(Shader, GlassBoxSpawnsRefractionButOpaqueSceneDoesNot) {
  Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
  s.materials.push_back(test::glass_material(1.5f));
  test::add_box(s, {-1, -1, 0.5f}, {1, 1, 1.5f}, 1);
  s.max_depth = 3;
  s.finalize_materials();
  RayCounters counters;
  const glm::vec3 l = centre_radiance(s, &counters);
  EXPECT_GT(counters.refraction, 0u);
  EXPECT_GT(counters.reflection, 0u);
  EXPECT_TRUE(std::isfinite(l.r) && l.r >= 0.0f);
  EXPECT_EQ(counters.nan_radiance, 0u);  // the output is finite by construction; no NaN made it
  // The opaque half (review: it was never rendered): the floor alone, at the same depth.
  Scene opaque = test::lit_floor(0.5f, 100.0f, 3.0f);
  opaque.max_depth = 3;
  RayCounters opaque_counters;
  centre_radiance(opaque, &opaque_counters);
  EXPECT_EQ(opaque_counters.refraction, 0u);
  EXPECT_EQ(opaque_counters.reflection, 0u);
  EXPECT_EQ(opaque_counters.shadow, 4u);
}

// The count the finiteness checks read: a NaN the shading makes (here from a Whitted
// material of NaN emission, which neither loading nor the glTF conversion would give)
// leaves the shader as 0 and is counted.
TEST(Shader, NanRadianceIsCountedAndLeavesAsZero) {
  Scene s = test::lit_floor(0.5f, 1.0f, 3.0f);
  s.whitted[0].emission = glm::vec3(std::numeric_limits<float>::quiet_NaN());
  RayCounters counters;
  const glm::vec3 l = centre_radiance(s, &counters);
  EXPECT_EQ(l, glm::vec3(0.0f));
  EXPECT_GE(counters.nan_radiance, 1u);
}

// glTF MASK: a coverage equal to alphaCutoff is opaque ("greater than or equal to" the
// cutoff), one ULP below it is cut out.
TEST(Shader, AlphaMaskAtExactlyTheCutoffIsOpaque) {
  for (const float alpha : {0.5f, std::nextafter(0.5f, 0.0f)}) {
    SCOPED_TRACE(alpha);
    Scene s = test::lit_floor(0.0f, 100.0f, 3.0f);
    s.lights.clear();
    s.background = glm::vec3(0.0f);
    s.materials[0].emissive = glm::vec3(1.0f);
    s.materials[0].alpha_mode = AlphaMode::Mask;
    s.materials[0].alpha_cutoff = 0.5f;
    s.materials[0].base_alpha = alpha;
    s.finalize_materials();
    ASSERT_TRUE(s.effects().alpha_mask);
    EXPECT_EQ(centre_radiance(s), glm::vec3(alpha >= 0.5f ? 1.0f : 0.0f));
  }
}

// A shading normal facing away from the viewer (vertex normals against the winding) shades
// as the geometric normal does; it never turns the lit side black.
TEST(Shader, AShadingNormalFacingAwayFromTheViewerShadesAsTheGeometricNormal) {
  const Scene flat = test::lit_floor(0.5f, 100.0f, 3.0f);
  Scene inverted = flat;
  for (glm::vec3& n : inverted.normals) n = -n;
  const glm::vec3 expected = centre_radiance(flat);
  ASSERT_GT(expected.r, 0.0f);
  EXPECT_EQ(centre_radiance(inverted), expected);
}

// An unlit floor that emits 1 under `sheets` sheets of `sheet` (z = 0.1, 0.2, ...), seen
// from above against a background of `background`.
Scene emitting_floor_under(const Material& sheet, int sheets, float background, float pitch = 0.1f) {
  Scene s = test::lit_floor(0.0f, 100.0f, 3.0f);
  s.lights.clear();
  s.background = glm::vec3(background);
  s.materials[0].emissive = glm::vec3(1.0f);
  s.materials.push_back(sheet);
  for (int k = 1; k <= sheets; ++k) {
    const float z = pitch * float(k);
    test::add_quad(s, {-10, -10, z}, {10, -10, z}, {10, 10, z}, {-10, 10, z}, 1);
  }
  s.finalize_materials();
  return s;
}

Material cut_out_sheet() {
  Material cut_out = test::diffuse_material(glm::vec3(1.0f));
  cut_out.alpha_mode = AlphaMode::Mask;
  cut_out.base_alpha = 0.0f;
  return cut_out;
}

// A camera ray passes up to kMaxSeeThroughLayers cut-out surfaces; behind one more it
// counts as a miss and sees the background.
TEST(Shader, ACameraRayPassesTheLimitsCutOutLayersAndMissesBehindOneMore) {
  static_assert(kMaxSeeThroughLayers >= 64, "foliage cards stack by the tens");
  for (const int sheets : {kMaxSeeThroughLayers, kMaxSeeThroughLayers + 1}) {
    SCOPED_TRACE(sheets);
    EXPECT_EQ(centre_radiance(emitting_floor_under(cut_out_sheet(), sheets, 0.25f, 2.8f / float(sheets))),
              glm::vec3(sheets <= kMaxSeeThroughLayers ? 1.0f : 0.25f));
  }
}

// A shadow ray passes up to kMaxSeeThroughLayers cut-out surfaces on its way to the
// light; one more blocks it.
TEST(Shader, AShadowRayPassesTheLimitsCutOutLayersAndIsBlockedByOneMore) {
  Scene plain = test::lit_floor(0.5f, 100.0f, 3.0f);
  plain.lights[0].position = {2.0f, 0.0f, 3.0f};
  const glm::vec3 lit = centre_radiance(plain);
  ASSERT_GT(lit.r, 0.0f);
  for (const int sheets : {kMaxSeeThroughLayers, kMaxSeeThroughLayers + 1}) {
    SCOPED_TRACE(sheets);
    Scene s = plain;
    s.materials.push_back(cut_out_sheet());
    // Small sheets across the shadow ray from the floor's centre to the light (x = 2 z / 3),
    // clear of the camera ray straight down at x = 0, between z = 0.2 and 2.7.
    for (int k = 0; k < sheets; ++k) {
      const float z = 0.2f + 2.5f * float(k) / float(sheets), x = 2.0f * z / 3.0f;
      test::add_quad(s, {x - 0.1f, -0.1f, z}, {x + 0.1f, -0.1f, z}, {x + 0.1f, 0.1f, z}, {x - 0.1f, 0.1f, z}, 1);
    }
    s.finalize_materials();
    EXPECT_EQ(centre_radiance(s), sheets <= kMaxSeeThroughLayers ? lit : glm::vec3(0.0f));
  }
}

// A ray blends up to kMaxBlendLayers BLEND surfaces over what lies behind them: black
// sheets of alpha 0.5 over a floor that emits 1 pass 0.5^n of it. One surface more is
// weighed by its alpha over nothing (it used to be shaded as opaque): a last sheet that
// emits 2^64 under the limit's black sheets gives 0.5^64 x 0.5 x 2^64 = 0.5, not 1.
TEST(Shader, BlendLayersPassTheirShareUpToTheLimitAndOneMoreIsWeighedByItsAlpha) {
  Material pane = test::diffuse_material(glm::vec3(0.0f));
  pane.alpha_mode = AlphaMode::Blend;
  pane.base_alpha = 0.5f;
  static_assert(kMaxBlendLayers >= 32, "decals and glazing stack beyond 8");
  const float pitch = 2.8f / float(kMaxBlendLayers + 1);
  for (const int sheets : {3, kMaxBlendLayers}) {
    SCOPED_TRACE(sheets);
    EXPECT_EQ(centre_radiance(emitting_floor_under(pane, sheets, 0.0f, pitch)), glm::vec3(std::ldexp(1.0f, -sheets)));
  }
  Scene s = emitting_floor_under(pane, kMaxBlendLayers, 0.0f, pitch);
  Material bright = pane;
  bright.emissive = glm::vec3(std::ldexp(1.0f, kMaxBlendLayers));
  s.materials.push_back(bright);
  test::add_quad(s, {-10, -10, 0.5f * pitch}, {10, -10, 0.5f * pitch}, {10, 10, 0.5f * pitch}, {-10, 10, 0.5f * pitch},
                 2);
  s.finalize_materials();
  EXPECT_EQ(centre_radiance(s), glm::vec3(0.5f));
}

// Radiance never leaves the shader negative: a negative emission (which loading would not
// give) leaves as 0, as NaN does.
TEST(Shader, NegativeRadianceLeavesAsZero) {
  Scene s = test::lit_floor(0.5f, 1.0f, 3.0f);
  s.lights.clear();
  s.whitted[0].emission = glm::vec3(-1.0f, 0.5f, -2.0f);
  EXPECT_EQ(centre_radiance(s), glm::vec3(0.0f, 0.5f, 0.0f));
}

// A black corner (no albedo, no highlight) traces no shadow ray, but the texture footprint
// takes the light as reaching it (its neighbours in the texture may be lit): its
// irradiance is the light's, I cos / (pi d^2), as at a lit corner.
TEST(Shader, AFootprintAtABlackCornerTakesTheLightAsReachingIt) {
  for (const bool black : {false, true}) {
    SCOPED_TRACE(black);
    Scene s = test::lit_floor(0.5f, 100.0f, 3.0f);
    if (black) s.whitted[0].diffuse = s.whitted[0].specular = glm::vec3(0.0f);
    const Bvh bvh = Bvh::build(s.positions);
    const Shader shader(s, bvh);
    const CameraRays rays(s.cameras[0], 9, 9);
    HiddenDetail detail;
    detail.footprint = true;
    SceneSource source(shader, rays, kSignatureNone, &detail);
    SceneSource::Probe probes[4];
    int4 signature;
    source.sample4(float4(4.5f), float4(4.5f), signature, probes);
    const float expected = 100.0f / (9.0f * kPi);
    EXPECT_NEAR(probes[0].footprint[0].irradiance.r, expected, 1e-5f * expected);
    EXPECT_EQ(source.counters.shadow, black ? 0u : 4u);
  }
}

TEST(Shader, ExtremeLightsStayFinite) {
  // The radiance equation of LitPlaneMatchesTheRadianceEquation (albedo 1, the light 1e-3
  // above the floor), up to the shader's cap of 1e30 (review: finite and >= 0 alone held
  // for any value the sanitizer lets out, 0 included).
  for (float intensity : {1e-6f, 1.0f, 1e9f, 1e20f, 1e30f}) {
    RayCounters counters;
    const glm::vec3 l = centre_radiance(test::lit_floor(1.0f, intensity, 1e-3f), &counters);
    const double exact = double(intensity) / 1e-6 * (1.0 / kPi + 0.04 * 3.0 / (2.0 * kPi));
    const double expected = std::min(exact, 1e30);
    EXPECT_NEAR(l.r, expected, 1e-3 * expected) << intensity;
    EXPECT_EQ(counters.nan_radiance, 0u) << intensity;
    // The cap is counted where it bit, and only there: the image cannot tell.
    EXPECT_EQ(counters.capped_radiance > 0, exact > 1e30) << intensity;
  }
}

// +Inf (here an emission no loader would give) leaves the shader at the cap, counted.
TEST(Shader, InfiniteRadianceIsCappedAndCounted) {
  Scene s = test::lit_floor(0.5f, 1.0f, 3.0f);
  s.whitted[0].emission = glm::vec3(std::numeric_limits<float>::infinity(), 0.0f, 0.0f);
  RayCounters counters;
  const glm::vec3 l = centre_radiance(s, &counters);
  EXPECT_EQ(l.r, 1e30f);
  EXPECT_GE(counters.capped_radiance, 1u);
  EXPECT_EQ(counters.nan_radiance, 0u);
}

}  // namespace
}  // namespace zz

namespace zz {
namespace {

TEST(Shader, EmissiveTextureModulatesTheEmissiveFactor) {
  // glTF: emission = emissiveFactor * emissiveTexture. A black texture must not glow.
  Scene s = test::lit_floor(0.0f, 100.0f, 3.0f);
  s.lights.clear();
  Texture black;
  black.width = black.height = 1;
  black.texels = {glm::vec4(0.0f, 0.25f, 0.0f, 1.0f)};
  s.textures.push_back(black);
  s.materials[0].emissive = glm::vec3(1.0f);
  s.materials[0].emissive_texture.index = 0;
  s.finalize_materials();
  const glm::vec3 l = centre_radiance(s);
  EXPECT_EQ(l, glm::vec3(0.0f, 0.25f, 0.0f));
}

// A smooth dielectric mirrors with Schlick's Fresnel from F0 = 0.04 (ior 1.5):
// F(cos 60) = 0.04 + 0.96 (1 - 0.5)^5 = 0.07. The existing mirror tests look at normal
// incidence or at metals, where the term is 0 or unused: an exponent of 4 changed no test.
TEST(Shader, ASmoothDielectricMirrorsWithSchlicksFresnel) {
  Scene s;
  Material glaze;
  glaze.base_color = glm::vec3(0.0f);
  glaze.metallic = 0.0f;
  glaze.roughness = 0.0f;
  s.materials = {glaze};
  test::add_quad(s, {-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}, 0);
  // The centre ray meets the floor at 60 degrees from its normal; its reflection sees the sky.
  s.cameras.push_back(Camera::look_at({0, 0, 1}, {std::sqrt(3.0f), 0, 0}, {0, 0, 1}, 0.3f));
  s.background = glm::vec3(1.0f);
  s.max_depth = 2;
  s.finalize_materials();
  const glm::vec3 l = centre_radiance(s);
  const float expected = 0.04f + 0.96f * std::pow(0.5f, 5.0f);
  EXPECT_NEAR(l.r, expected, 1e-4f);
  EXPECT_NEAR(l.g, expected, 1e-4f);
}

// A camera inside an absorbing volume (its rays are not known to be inside it) sees what lies
// beyond the volume's back face through exp(-sigma d) of the path inside (Beer's law): the
// exit face is a back face, and the segment before it is the volume's. Mutation testing found
// that counting only segments of rays known to be inside changed no test.
TEST(Shader, ACameraInsideAVolumeSeesThroughItsAbsorption) {
  Scene s;
  Material glow;
  glow.base_color = glm::vec3(0.0f);
  glow.emissive = glm::vec3(1.0f);
  Material tinted = test::glass_material(1.0f);  // ior 1: no bending, no Fresnel
  tinted.attenuation_color = glm::vec3(0.05f, 1.0f, 1.0f);
  tinted.attenuation_distance = 0.5f;
  s.materials = {glow, tinted};
  test::add_quad(s, {-20, -20, -3}, {20, -20, -3}, {20, 20, -3}, {-20, 20, -3}, 0);
  test::add_box(s, {-1, -1, -1}, {1, 1, 1}, 1);
  s.cameras.push_back(Camera::look_at({0, 0, 0.2f}, {0, 0, -1}, {0, 1, 0}, 0.3f));  // 1.2 from the exit face
  s.background = glm::vec3(0.0f);
  s.max_depth = 8;
  s.finalize_materials();
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  const CameraRays rays(s.cameras[0], 9, 9);
  SceneSource source(shader, rays);
  const Rgb4 c = source.sample4(float4(4.5f), float4(4.5f));
  const float sigma = -std::log(0.05f) / 0.5f;  // red: 5 % left after 0.5
  ASSERT_GT(c.g[0], 0.5f);
  EXPECT_NEAR(c.r[0] / c.g[0], std::exp(-sigma * 1.2f), 1e-4f);
}

}  // namespace

}  // namespace zz
