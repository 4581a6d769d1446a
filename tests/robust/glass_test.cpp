// Glass: total internal reflection, the critical angle, nested and touching glass, IOR 1
// (must vanish) and trace depth exhausted inside glass. With no lights, no diffuse and a
// white background, Whitted glass only redistributes the background: the Fresnel weights
// F and 1 - F sum to 1, so every pixel lies in [0, 1] (0 where a path ran out of depth),
// and adding bounces can only add light.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/scene_source.h"
#include "robust_scenes.h"

namespace zz {
namespace {

Scene glass_box_scene(float ior, int max_depth) {
  Scene s;
  s.materials.push_back(test::glass_material(ior));
  test::add_box(s, {-1, -1, -1}, {1, 1, 1}, 0);
  s.background = glm::vec3(1.0f);
  s.cameras.push_back(Camera::look_at({2.5f, -3.0f, 2.0f}, {0, 0, 0}, {0, 0, 1}, 0.9f));
  s.max_depth = max_depth;
  s.finalize_materials();
  return s;
}

struct Range {
  float lo = 1e30f, hi = -1e30f;
  double mean = 0.0;
};

Range range_of(const Film& f) {
  Range r;
  for (const glm::vec3& c : f.radiance)
    for (int i = 0; i < 3; ++i) {
      r.lo = std::min(r.lo, c[i]);
      r.hi = std::max(r.hi, c[i]);
      r.mean += c[i];
    }
  r.mean /= 3.0 * double(f.radiance.size());
  return r;
}

constexpr float kEnergyTolerance = 1e-5f;  // float rounding of F + (1 - F)

TEST(Glass, EnergyBoundedAndMonotoneInDepthUpToExhaustion) {
  double previous = -1.0;
  for (int depth : {0, 1, 2, 3, 4, 6, 8, 12, 16}) {
    const Film f = robust::render(glass_box_scene(1.5f, depth), robust::settings(48, 48, AaMode::None));
    ASSERT_EQ(robust::bad_values(f), 0u);
    const Range r = range_of(f);
    std::printf("[ glass ] depth %2d: radiance in [%g, %g], mean %.6f\n", depth, r.lo, r.hi, r.mean);
    EXPECT_GE(r.lo, 0.0f);
    EXPECT_LE(r.hi, 1.0f + kEnergyTolerance);
    EXPECT_GE(r.mean, previous - 1e-6) << "more bounces removed light";
    previous = r.mean;
  }
}

TEST(Glass, TotalInternalReflectionAndTheCriticalAngle) {
  // Inside a glass slab (n = 1.5), rays hit the top face at angles around the critical
  // angle asin(1/1.5) = 41.81 deg: beyond it all light is reflected (F = 1), just before
  // it the transmitted ray leaves tangentially. Radiance stays in [0, 1].
  Scene s;
  s.materials.push_back(test::glass_material(1.5f));
  test::add_box(s, {-50, -50, -1}, {50, 50, 1}, 0);
  s.background = glm::vec3(1.0f);
  s.cameras.push_back(Camera::look_at({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 0.5f));  // inside the slab
  s.max_depth = 8;
  s.finalize_materials();
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  const double critical = std::asin(1.0 / 1.5);
  for (double delta : {-1e-2, -1e-4, -1e-6, 0.0, 1e-6, 1e-4, 1e-2}) {
    const double incidence = critical + delta;  // angle to the top face's normal (+z)
    RayPacket4 rays;
    const float dx = float(std::sin(incidence)), dz = float(std::cos(incidence));
    rays.ox = rays.oy = rays.oz = float4(0.0f);
    rays.dx = float4(dx), rays.dy = float4(0.0f), rays.dz = float4(dz);
    rays.tmax = float4(kInfinity);
    RayCounters counters;
    const Rgb4 c = shader.trace4(rays, mask4(true), 0, counters);
    for (int i = 0; i < 4; ++i) {
      ASSERT_TRUE(std::isfinite(c.r[i])) << delta;
      EXPECT_GE(c.r[i], 0.0f) << delta;
      EXPECT_LE(c.r[i], 1.0f + kEnergyTolerance) << delta;
      // Past the critical angle the ray stays in the slab, reflected between its faces at
      // the same angle, and never reaches the white background (review: only the range was
      // checked); well before it most of the light gets out.
      if (delta >= 1e-4) {  // (at the angle itself rounding decides)
        EXPECT_EQ(c.r[i], 0.0f) << delta;
      }
      if (delta <= -1e-2) {
        EXPECT_GT(c.r[i], 0.9f) << delta;
      }
    }
    // Fresnel itself: exactly 1 past the critical angle, continuous up to it.
    const float f = fresnel_dielectric(float(std::cos(incidence)), 1.5f);
    if (delta >= 1e-4) {
      EXPECT_EQ(f, 1.0f) << delta;
    }
    if (delta <= -1e-4) {
      EXPECT_LT(f, 1.0f) << delta;
    }
    EXPECT_GE(f, 0.0f);
    EXPECT_LE(f, 1.0f);
    std::printf("[ glass ] critical%+g rad: F = %.6f, L = %.6f\n", delta, f, c.r[0]);
  }
}

// Fresnel reflectance of unpolarised light at a smooth dielectric interface, written out
// here (Born & Wolf) rather than taken from the shader: eta = n_transmitted / n_incident.
double fresnel_reference(double cos_i, double eta) {
  const double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1.0) return 1.0;  // total internal reflection
  const double cos_t = std::sqrt(1.0 - sin_t2);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// What a ray inside a solid slab brings back, heading for one face at `depth` with the
// path's throughput so far: the faces are parallel, so every inner ray meets them at the
// same angle, with reflectance F. Leaving through the top it reaches a glow of 1, through
// the bottom a black background. Whitted's tree summed as the shader prunes it: a ray is
// spawned below the trace depth and while its path keeps Shader::kMinThroughput.
double slab_inner(double f, int depth, int max_depth, double path, bool upwards) {
  if (depth >= max_depth) return 0.0;
  double l = 0.0;
  if (f < 1.0 && path * (1.0 - f) >= Shader::kMinThroughput && upwards) l += 1.0 - f;
  if (path * f >= Shader::kMinThroughput) l += f * slab_inner(f, depth + 1, max_depth, path * f, !upwards);
  return l;
}

// A solid slab (n = 1.5, z in [-1, 1]) under a glowing ceiling (z = 3) over a black
// background. With no cutoff and unlimited depth the sums have closed forms:
//   from inside, upwards:  (1 - F) (1 + F^2 + F^4 + ...) = 1 / (1 + F), and 0 beyond the
//                          critical angle, where no path ever leaves;
//   from below the slab:   (1 - F)^2 (1 + F^2 + ...)   = (1 - F) / (1 + F)
// (F the same from either side: Stokes' relations). The renderer must give the pruned
// sum exactly and the closed form within what the throughput cutoff drops. Catches a
// wrong relative index on the way out, a ray that leaves from the wrong side, and
// Fresnel weights that do not sum to 1.
TEST(Glass, ASlabsInnerReflectionsSumToTheirClosedForm) {
  Scene s;
  Material glow;
  glow.base_color = glm::vec3(0.0f);
  glow.emissive = glm::vec3(1.0f);
  s.materials = {test::glass_material(1.5f), glow};
  // Wide enough that no ray reaches the slab's rim within the trace depth (85 deg: 550).
  test::add_box(s, {-2000, -2000, -1}, {2000, 2000, 1}, 0);
  test::add_quad(s, {-3000, -3000, 3}, {3000, -3000, 3}, {3000, 3000, 3}, {-3000, 3000, 3}, 1);
  s.background = glm::vec3(0.0f);
  s.cameras.push_back(Camera::look_at({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 0.5f));
  s.max_depth = 24;
  s.finalize_materials();
  ASSERT_FALSE(s.whitted[0].thin_walled);
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  const double critical = std::asin(1.0 / 1.5);

  // Angles to +z, in degrees, of rays from inside the slab and from below it.
  struct Case {
    float origin_z;
    double degrees[4];
  };
  for (const Case& c : {Case{0.0f, {0, 20, 35, 41}}, Case{0.0f, {43, 50, 65, 85}}, Case{-3.0f, {0, 30, 60, 80}}}) {
    const bool inside = c.origin_z == 0.0f;
    RayPacket4 rays;
    alignas(16) float dx[4], dz[4];
    for (int i = 0; i < 4; ++i) {
      dx[i] = float(std::sin(glm::radians(c.degrees[i])));
      dz[i] = float(std::cos(glm::radians(c.degrees[i])));
    }
    rays.ox = rays.oy = float4(0.0f);
    rays.oz = float4(c.origin_z);
    rays.dx = float4::load(dx), rays.dy = float4(0.0f), rays.dz = float4::load(dz);
    rays.tmax = float4(kInfinity);
    RayCounters counters;
    const Rgb4 l = shader.trace4(rays, mask4(true), 0, counters);
    for (int i = 0; i < 4; ++i) {
      const double outer = glm::radians(c.degrees[i]);
      const double inner = inside ? outer : std::asin(std::sin(outer) / 1.5);  // Snell
      const double f = fresnel_reference(std::cos(inner), 1.0 / 1.5);
      double pruned, closed;
      if (inside) {
        pruned = slab_inner(f, 0, s.max_depth, 1.0, true);
        closed = inner > critical ? 0.0 : 1.0 / (1.0 + f);
      } else {
        const double entering = fresnel_reference(std::cos(outer), 1.5);
        EXPECT_NEAR(entering, f, 1e-12) << "Stokes";
        pruned = (1.0 - entering) * slab_inner(f, 1, s.max_depth, 1.0 - entering, true);
        closed = (1.0 - f) / (1.0 + f);
      }
      const std::string what = std::to_string(c.degrees[i]) + (inside ? " deg inside" : " deg below");
      std::printf("[ glass ] slab, %s: F = %.6f, L = %.7f (pruned sum %.7f, closed form %.7f)\n", what.c_str(), f,
                  l.r[i], pruned, closed);
      EXPECT_NEAR(l.r[i], pruned, 2e-6) << what;
      // The cutoff drops terms below 1/1024 of the radiance each; here, at most 4 of them.
      EXPECT_NEAR(l.r[i], closed, 4.0 * Shader::kMinThroughput) << what;
      EXPECT_EQ(l.g[i], l.r[i]);
    }
  }
}

// KHR_materials_volume: a transmissive surface without a thickness is a thin wall, light
// crosses it unbent; with one it is a solid's face and bends light (Snell). A sheet tilted
// 45 deg over a floor that glows only where x > 0: a ray straight down at x = -0.05 lands
// on the dark half through a thin wall, but bent by 17 deg it reaches x = +0.27 through a
// solid's face. Either way the sheet transmits 1 - F(45 deg, 1.5) = 0.9497 of the glow.
TEST(Glass, AThinWallLetsLightThroughUnbentAndASolidBendsIt) {
  for (const bool solid : {false, true}) {
    Scene s;
    Material sheet = test::glass_material(1.5f);
    sheet.thickness = solid ? 0.5f : 0.0f;
    Material glow, dark;
    glow.base_color = dark.base_color = glm::vec3(0.0f);
    glow.emissive = glm::vec3(1.0f);
    s.materials = {sheet, glow, dark};
    test::add_quad(s, {-0.5f, -1, 0.5f}, {0.5f, -1, 1.5f}, {0.5f, 1, 1.5f}, {-0.5f, 1, 0.5f}, 0);  // z = 1 + x
    test::add_quad(s, {0, -5, 0}, {5, -5, 0}, {5, 5, 0}, {0, 5, 0}, 1);
    test::add_quad(s, {-5, -5, 0}, {0, -5, 0}, {0, 5, 0}, {-5, 5, 0}, 2);
    s.background = glm::vec3(0.0f);
    s.cameras.push_back(Camera::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.5f));
    s.max_depth = 4;
    s.finalize_materials();
    ASSERT_EQ(s.whitted[0].thin_walled, !solid);
    const Bvh bvh = Bvh::build(s.positions);
    const Shader shader(s, bvh);
    RayPacket4 rays;
    alignas(16) const float x[4] = {-0.05f, 0.05f, -0.2f, 0.2f};
    rays.ox = float4::load(x);
    rays.oy = float4(0.0f), rays.oz = float4(5.0f);
    rays.dx = rays.dy = float4(0.0f), rays.dz = float4(-1.0f);
    rays.tmax = float4(kInfinity);
    RayCounters counters;
    const Rgb4 c = shader.trace4(rays, mask4(true), 0, counters);
    const float through = 1.0f - fresnel_dielectric(std::cos(glm::radians(45.0f)), 1.0f / 1.5f);
    EXPECT_NEAR(through, 0.9497f, 1e-3f);
    EXPECT_NEAR(c.r[0], solid ? through : 0.0f, 1e-4f) << "x = -0.05, solid " << solid;
    EXPECT_NEAR(c.r[1], through, 1e-4f) << "x = +0.05, solid " << solid;
    EXPECT_NEAR(c.r[3], through, 1e-4f) << "x = +0.2, solid " << solid;
    EXPECT_NEAR(c.r[2], solid ? through : 0.0f, 1e-4f) << "x = -0.2 (bent to +0.15), solid " << solid;
    EXPECT_EQ(counters.refraction, 4u);
  }
}

TEST(Glass, NestedAndTouchingGlassStaysInRange) {
  for (int variant = 0; variant < 3; ++variant) {
    Scene s;
    s.materials.push_back(test::glass_material(1.5f));
    s.materials.push_back(test::glass_material(1.33f));
    s.materials.push_back(test::glass_material(2.4f));
    test::add_box(s, {-1, -1, -1}, {1, 1, 1}, 0);
    if (variant == 0) test::add_box(s, {-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, 1);  // nested
    if (variant == 1) test::add_box(s, {1, -1, -1}, {3, 1, 1}, 2);                     // touching face
    if (variant == 2) test::add_box(s, {-1, -1, -1}, {1, 1, 1}, 1);                    // coincident
    s.background = glm::vec3(1.0f);
    s.cameras.push_back(Camera::look_at({3.0f, -4.0f, 2.5f}, {0.5f, 0, 0}, {0, 0, 1}, 0.9f));
    s.max_depth = 12;
    s.finalize_materials();
    for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
      const Film f = robust::render(s, robust::settings(48, 40, aa));
      ASSERT_EQ(robust::bad_values(f), 0u) << variant;
      const Range r = range_of(f);
      std::printf("[ glass ] variant %d aa %d: [%g, %g]\n", variant, int(aa), r.lo, r.hi);
      EXPECT_LE(r.hi, 1.0f + kEnergyTolerance) << variant;
    }
  }
}

TEST(Glass, IorOneVanishesFromTheWholeImage) {
  // An emissive floor seen through an IOR-1 glass box: no refraction, no Fresnel, the
  // image equals the floor alone (lights off: shadow rays treat glass as opaque).
  Scene plain = robust::emissive_wall({0.25f, 0.5f, 0.75f});
  plain.background = glm::vec3(0.1f);
  plain.cameras[0] = Camera::look_at({0.5f, -3.0f, 4.0f}, {0, 0, 0}, {0, 0, 1}, 0.8f);
  Scene glass = plain;
  glass.materials.push_back(test::glass_material(1.0f));
  test::add_box(glass, {-1, -1, 0.5f}, {1, 1, 1.5f}, 1);
  glass.max_depth = 4;
  glass.finalize_materials();
  for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
    const Film a = robust::render(plain, robust::settings(64, 48, aa));
    const Film b = robust::render(glass, robust::settings(64, 48, aa));
    float worst = 0.0f;
    for (size_t i = 0; i < a.radiance.size(); ++i)
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a.radiance[i][k] - b.radiance[i][k]));
    std::printf("[ glass ] IOR 1.0 box, aa %d: max |difference| %g\n", int(aa), worst);
    EXPECT_LE(worst, 1e-6f);
  }
}

}  // namespace
}  // namespace zz
