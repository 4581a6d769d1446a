// The analytic highlight flag's geometry (render/specular_peak.h) and, through the
// renderer, a pinpoint highlight between a pixel's corners.
#include "render/specular_peak.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "aa/adaptive_pixel.h"
#include "aa/hidden_detail.h"
#include "aa/lattice.h"
#include "render/lighting.h"
#include "render/renderer.h"
#include "render/scene_source.h"
#include "test_scenes.h"

namespace zz {
namespace {

// The probe of the camera ray through pixel centre (20, 20) of a 40² frame of `s`'s first
// camera (straight down in the scenes below), as level 1 records it for the highlight flag.
SceneSource::Probe centre_probe(const Shader& shader, const CameraRays& camera) {
  SceneSource source(shader, camera, kSignatureNone);
  SceneSource::Probe probes[4];
  int4 signature;
  source.sample4(float4(20.0f), float4(20.0f), signature, probes);
  return probes[0];
}
SceneSource::Probe centre_probe(const Scene& s) {
  const Bvh bvh = Bvh::build(s.positions);
  return centre_probe(Shader(s, bvh), CameraRays(s.cameras[0], 40, 40));
}

TEST(SpecularPeak, DistanceFromTheOriginToTheHullOfFourPoints) {
  const glm::vec2 around[4] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
  EXPECT_EQ(origin_distance_to_hull(around), 0.0f);
  const glm::vec2 twisted[4] = {{-1, -1}, {1, 1}, {1, -1}, {-1, 1}};  // order does not matter
  EXPECT_EQ(origin_distance_to_hull(twisted), 0.0f);
  const glm::vec2 off[4] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}};
  EXPECT_NEAR(origin_distance_to_hull(off), std::sqrt(2.0f), 1e-6f);
  const glm::vec2 edge[4] = {{-1, 3}, {1, 3}, {-1, 5}, {1, 5}};  // nearest point inside an edge
  EXPECT_NEAR(origin_distance_to_hull(edge), 3.0f, 1e-6f);
  const glm::vec2 point[4] = {{0, 2}, {0, 2}, {0, 2}, {0, 2}};  // degenerate: one point
  EXPECT_NEAR(origin_distance_to_hull(point), 2.0f, 1e-6f);
  const glm::vec2 line[4] = {{-1, 0}, {1, 0}, {-1, 0}, {1, 0}};  // degenerate through the origin
  EXPECT_EQ(origin_distance_to_hull(line), 0.0f);
  const glm::vec2 last[4] = {{2, 2}, {2, 1}, {1, 2}, {1, 1}};  // the nearest point is every segment's far end
  EXPECT_NEAR(origin_distance_to_hull(last), std::sqrt(2.0f), 1e-6f);
  const glm::vec2 bad[4] = {{std::numeric_limits<float>::quiet_NaN(), 0}, {1, 0}, {0, 1}, {1, 1}};
  EXPECT_TRUE(std::isinf(origin_distance_to_hull(bad)));
}

// The flag's cheap rejection: exp(-2 s d^2) is never below the lobe, and for the narrow
// lobes of glossy surfaces (100 <= s <= 1e5) close to it wherever the lobe is at least a
// hundredth of its peak, so that it rejects nearly what the exact lobe would. (Wide lobes
// it bounds loosely: the exact lobe is then computed, as before.)
TEST(SpecularPeak, TheLobeBoundHoldsAndIsTight) {
  for (float s : {1.0f, 2.0f, 10.0f, 100.0f, 1e3f, 1e4f, 1e6f})
    for (int i = 0; i <= 4000; ++i) {
      const float d = 2.0f * float(i) / 4000.0f;
      const float lobe = lobe_at(d, s), bound = lobe_bound(d, s);
      ASSERT_GE(bound, lobe) << "s " << s << " d " << d;
      if (s >= 100.0f && s <= 1e5f && lobe > 0.01f) {
        EXPECT_LT(bound, 1.15f * lobe) << "s " << s << " d " << d;
      }
    }
}

TEST(SpecularPeak, BilinearQuadArea) {
  const glm::vec2 unit[4] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};  // TL, TR, BL, BR
  EXPECT_FLOAT_EQ(bilinear_quad_area(unit), 1.0f);
  const glm::vec2 sheared[4] = {{0, 0}, {2, 0}, {1, 3}, {3, 3}};
  EXPECT_FLOAT_EQ(bilinear_quad_area(sheared), 6.0f);
}

// A glossy floor z = 0 (Phong exponent 10000, specular 0.04), one light and a viewer
// placed so that the highlight's peak, the mirror point, is the origin.
struct GlossyFloor {
  Scene scene;
  glm::vec3 eye{-1.0f, 0.0f, 1.0f};
  float shininess = 10000.0f;
  GlossyFloor() {
    Light light;
    light.position = {1.0f, 0.0f, 1.0f};
    scene.lights.push_back(light);
  }
  SurfaceProbe probe(glm::vec3 p) const {
    return {p, {0, 0, 1}, glm::normalize(eye - p), glm::vec3(0.04f), shininess, 0u};
  }
  // The pixel whose corners are (x0..x1) x (y0..y1) on the floor.
  void corners(float x0, float x1, float y0, float y1, SurfaceProbe out[4]) const {
    out[0] = probe({x0, y0, 0}), out[1] = probe({x1, y0, 0}), out[2] = probe({x0, y1, 0}), out[3] = probe({x1, y1, 0});
  }
  // The shader's highlight radiance at p (shader.cpp's per-light term, specular part).
  float highlight(glm::vec3 p) const {
    const SurfaceProbe s = probe(p);
    glm::vec3 wi, scale;
    float distance;
    light_towards(scene.lights[0], p, wi, distance, scale);
    const float cos_n = glm::dot(s.normal, wi);
    const glm::vec3 r = 2.0f * cos_n * s.normal - wi;
    const float lobe = std::pow(std::max(0.0f, glm::dot(r, s.view)), s.shininess);
    return 0.04f * phong_normalisation(s.shininess) * lobe * scale.r * cos_n;
  }
  // Its true mean over the pixel, by brute force.
  double true_mean(float x0, float x1, float y0, float y1) const {
    const int n = 400;
    double sum = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        sum += highlight({x0 + (x1 - x0) * (i + 0.5f) / n, y0 + (y1 - y0) * (j + 0.5f) / n, 0.0f});
    return sum / (double(n) * n);
  }
};

TEST(SpecularPeak, APinpointHighlightBetweenTheCornersIsFound) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(-0.02f, 0.025f, -0.03f, 0.02f, c);
  const double corners = 0.25 * (f.highlight(c[0].position) + f.highlight(c[1].position) +
                                 f.highlight(c[2].position) + f.highlight(c[3].position));
  const double truth = f.true_mean(-0.02f, 0.025f, -0.03f, 0.02f);
  ASSERT_LT(corners, 0.01 * truth);  // no corner sees it
  const glm::vec3 hidden = hidden_highlight(f.scene, c, glm::vec3(1e-3f));
  // What the pixel misses, estimated from the corners alone, within 30 % of the truth.
  EXPECT_NEAR(hidden.r, truth - corners, 0.3 * truth);
  EXPECT_EQ(hidden.r, hidden.g);
}

// The corners' light terms come from light_towards4 for every kind of light (its lanes
// equal the scalar light_towards: lighting4_test.cpp); a spot whose cone is the whole
// sphere lights as the point does (its cone factor is 1), so the flag must give the very
// same floats and points for both, over pixels around, on and off the peak.
TEST(SpecularPeak, ASpotWhoseConeIsTheWholeSphereFlagsAsThePointLight) {
  GlossyFloor point, spot;
  Light& cone = spot.scene.lights[0];
  cone.type = Light::Type::Spot;
  cone.direction = {0.0f, 0.0f, -1.0f};
  cone.inner_cone = cone.outer_cone = 3.14159265f;
  SurfaceProbe c[4];
  int nonzero = 0;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const float x0 = -0.18f + 0.05f * float(i), y0 = -0.17f + 0.05f * float(j);  // (3, 3) holds the peak
      point.corners(x0, x0 + 0.045f, y0, y0 + 0.05f, c);
      uint32_t point_points = 0, spot_points = 0;
      const glm::vec3 a = hidden_highlight(point.scene, c, glm::vec3(1e-5f), nullptr,
                                           std::numeric_limits<float>::infinity(), nullptr, &point_points);
      const glm::vec3 b = hidden_highlight(spot.scene, c, glm::vec3(1e-5f), nullptr,
                                           std::numeric_limits<float>::infinity(), nullptr, &spot_points);
      EXPECT_EQ(a, b) << i << ", " << j;
      EXPECT_EQ(point_points, spot_points) << i << ", " << j;
      nonzero += a.r > 0.0f;
    }
  EXPECT_GT(nonzero, 0);
}

// Just outside the pixel the peak still spills into it: the lobe's integral beyond the
// hull's distance is a Gaussian tail, half of erfc (one side of the edge), not all of it.
TEST(SpecularPeak, APeakJustOutsideThePixelIsEstimatedByTheGaussianTail) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(0.004f, 0.049f, -0.03f, 0.02f, c);  // the peak 0.004 left of the pixel's left edge
  const double corners = 0.25 * (f.highlight(c[0].position) + f.highlight(c[1].position) +
                                 f.highlight(c[2].position) + f.highlight(c[3].position));
  const double truth = f.true_mean(0.004f, 0.049f, -0.03f, 0.02f);
  ASSERT_LT(corners, 0.1 * truth);  // the corners see little of it
  EXPECT_NEAR(hidden_highlight(f.scene, c, glm::vec3(1e-3f)).r, truth - corners, 0.3 * truth);
}

// A wide lobe (exponent 100) peaking mid-pixel: its corners' mean misses a good part of it,
// more than `visible`, so the light is examined (the cull's bound on the corners' error is
// s span^2 / 2 of the amplitude) and the miss estimated.
TEST(SpecularPeak, AWideLobeMissedByTheCornersIsEstimated) {
  GlossyFloor f;
  f.shininess = 100.0f;
  SurfaceProbe c[4];
  f.corners(-0.08f, 0.08f, -0.08f, 0.08f, c);
  const double corners = 0.25 * (f.highlight(c[0].position) + f.highlight(c[1].position) +
                                 f.highlight(c[2].position) + f.highlight(c[3].position));
  const double truth = f.true_mean(-0.08f, 0.08f, -0.08f, 0.08f);
  ASSERT_GT(truth - corners, 0.2 * truth);
  const glm::vec3 visible(float(0.5 * (truth - corners)));
  EXPECT_NEAR(hidden_highlight(f.scene, c, visible).r, truth - corners, 0.3 * (truth - corners));
}

// Shadow at some corners only (a shadow's edge across the pixel) leaves the light examined:
// only a light blocked at all four corners is skipped.
TEST(SpecularPeak, ALightBlockedAtSomeCornersIsStillExamined) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(-0.02f, 0.025f, -0.03f, 0.02f, c);
  const glm::vec3 open = hidden_highlight(f.scene, c, glm::vec3(1e-3f));
  ASSERT_GT(open.r, 0.0f);
  c[0].blocked = c[3].blocked = 1u;
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e-3f)), open);
}

// The pixel's extent around corner 0 reaches its farthest corner, whichever it is: here the
// BR corner, right under the light (1 from it; corner 0 5.1, the other two within 2.83 of
// corner 0). The light is not culled by an inverse-square bound from corner 0, and the
// highlight between the corners (the peak at the origin) is found.
TEST(SpecularPeak, ThePixelsExtentReachesEveryCorner) {
  const GlossyFloor f;
  const SurfaceProbe c[4] = {f.probe({-4, 0, 0}), f.probe({-2, 2, 0}), f.probe({-2, -2, 0}), f.probe({1, 0, 0})};
  const glm::vec3 visible = 0.5f * 0.04f * phong_normalisation(f.shininess) * f.scene.lights[0].intensity;
  EXPECT_GT(hidden_highlight(f.scene, c, visible).r, 0.0f);
}

// The narrow lobe's estimate, its Gaussian tail spread over the pixel, is capped by the
// lobe's largest value in the pixel: where every half vector lies beyond the lobe's reach
// (|n - h| >= 0.78 turns the mirror direction past 90 degrees, lobe_at = 0) nothing is
// hidden, however small `visible`. One point, h = +z, four normals with |n_xy| = 0.9 or 1
// at +-30 degrees about the light's side.
TEST(SpecularPeak, NothingHiddenWhereTheLobeIsZeroAcrossThePixel) {
  const GlossyFloor f;
  const glm::vec3 normals[4] = {{0.9f * 0.866f, 0.45f, 0.436f}, {0.866f, 0.5f, 0.0f},
                                {0.9f * 0.866f, -0.45f, 0.436f}, {0.866f, -0.5f, 0.0f}};
  SurfaceProbe c[4];
  for (int k = 0; k < 4; ++k) {
    c[k] = f.probe({0, 0, 0});
    c[k].normal = glm::normalize(normals[k]);
    c[k].shininess = 50.0f;
  }
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e-37f)), glm::vec3(0.0f));
}

// A light within the pixel's own reach (nearer corner 0 than the farthest corner is) has no
// inverse-square bound there: it is examined, however large the pixel.
TEST(SpecularPeak, ALightWithinThePixelsReachIsNotCulledByItsDistance) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(-0.5f, 10.0f, -0.5f, 10.0f, c);  // the peak inside; the light 1.9 from corner 0, the pixel 14.8 across
  EXPECT_GT(hidden_highlight(f.scene, c, glm::vec3(0.5f)).r, 0.0f);
}

// Each light's miss is weighted by the corners' mean incident light: a range window that
// leaves the left corners unlit (same half vectors, so the same lobe) lowers the estimate by
// the ratio of the corners' summed incident light, not by that of the brightest corner's.
TEST(SpecularPeak, AHighlightIsWeightedByTheCornersMeanIncidentLight) {
  GlossyFloor point, ranged;
  ranged.scene.lights[0].range = 1.42f;  // the left corners 1.428 from the light, the right 1.397
  SurfaceProbe c[4];
  point.corners(-0.02f, 0.025f, -0.03f, 0.02f, c);
  double incident_point = 0.0, incident_ranged = 0.0;
  for (const SurfaceProbe& p : c) {
    glm::vec3 wi, scale;
    float distance;
    light_towards(point.scene.lights[0], p.position, wi, distance, scale);
    incident_point += scale.r * glm::dot(p.normal, wi);
    if (light_towards(ranged.scene.lights[0], p.position, wi, distance, scale))
      incident_ranged += scale.r * glm::dot(p.normal, wi);
  }
  ASSERT_GT(incident_ranged, 0.0);
  const glm::vec3 all = hidden_highlight(point.scene, c, glm::vec3(1e-4f));
  const glm::vec3 windowed = hidden_highlight(ranged.scene, c, glm::vec3(1e-4f));
  ASSERT_GT(all.r, 0.0f);
  EXPECT_NEAR(windowed.r / all.r, incident_ranged / incident_point, 0.01 * incident_ranged / incident_point);
}

// A corner the light does not reach (beyond its range) saw none of its highlight, even at
// the peak: the pixel's lit part may hold it. The peak at corner 0, which lies beyond the
// range, and the right corners within it.
TEST(SpecularPeak, AnUnlitCornerAtThePeakSawNoneOfIt) {
  GlossyFloor f;
  f.scene.lights[0].range = 1.40f;  // corner 0 1.414 from the light, the right corners 1.38
  SurfaceProbe c[4];
  f.corners(0.0f, 0.05f, 0.0f, 0.05f, c);
  EXPECT_GT(hidden_highlight(f.scene, c, glm::vec3(1e-6f)).r, 0.0f);
}

// Where it may show: the peak at (0, 0) lies a quarter of the way across the pixel from
// its TL corner, so the lattice points the flag names are around (0.25, 0.25), the one
// nearest the peak among them, and none in the far half (the lobe, exponent 10000, spans
// a few hundredths of the pixel's range of half vectors). A pixel it misses names nothing.
TEST(SpecularPeak, APinpointHighlightNamesTheLatticePointsAroundItsPeak) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(-0.025f, 0.075f, -0.025f, 0.075f, c);
  uint32_t points = 0;
  const glm::vec3 hidden = hidden_highlight(f.scene, c, glm::vec3(1e-2f), nullptr,
                                            std::numeric_limits<float>::infinity(), nullptr, &points);
  ASSERT_GT(hidden.r, 0.0f);
  ASSERT_NE(points, 0u);
  EXPECT_NE(points, kAllLatticePoints);
  int nearest = 0;
  float nearest_distance = 2.0f;
  for (int p = 0; p < kLatticePoints; ++p) {
    const glm::vec2 at(kLattice[size_t(p)].u, kLattice[size_t(p)].v);
    const float from_peak = glm::length(at - glm::vec2(0.25f, 0.25f));
    if (from_peak < nearest_distance) nearest_distance = from_peak, nearest = p;
    if (from_peak > 0.5f) {
      EXPECT_EQ((points >> p) & 1u, 0u) << "point " << p << " is " << from_peak << " from the peak";
    }
  }
  EXPECT_EQ((points >> nearest) & 1u, 1u);
  // Away from the peak nothing is hidden and no point is named.
  f.corners(0.2f, 0.3f, 0.2f, 0.3f, c);
  uint32_t far_points = 0;
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e-2f), nullptr, std::numeric_limits<float>::infinity(), nullptr,
                             &far_points),
            glm::vec3(0.0f));
  EXPECT_EQ(far_points, 0u);
}

// A lobe narrower than the lattice's spacing may reach visible x 25 / 4 at none of the 25
// points: then the one point nearest its peak is named, and only it. The peak (0, 0) sits
// at (0.31, 0.73) of the pixel, 0.09 from P_6 and 0.11 from P_10, the other points
// 0.22 or more away; with a lower `visible` both P_6 and P_10 reach the zone's threshold.
TEST(SpecularPeak, ALobeBetweenLatticePointsNamesOnlyTheNearest) {
  const GlossyFloor f;
  const float w = 0.12f;
  SurfaceProbe c[4];
  f.corners(-0.31f * w, 0.69f * w, -0.73f * w, 0.27f * w, c);
  uint32_t points = 0;
  const glm::vec3 hidden = hidden_highlight(f.scene, c, glm::vec3(2.2f), nullptr,
                                            std::numeric_limits<float>::infinity(), nullptr, &points);
  ASSERT_GT(hidden.r, 0.0f);
  EXPECT_EQ(points, 1u << 6);
  points = 0;
  hidden_highlight(f.scene, c, glm::vec3(0.4f), nullptr, std::numeric_limits<float>::infinity(), nullptr, &points);
  EXPECT_EQ(points, (1u << 6) | (1u << 10));
}

// A corner whose half vector is 45 degrees or more off its normal sits where the lobe's
// cosine is clamped to pi / 2, and cosf(pi / 2) is a hair below 0: raised to a
// non-integer exponent (a mean of several materials' exponents is one) it was NaN, and a
// NaN corner silenced the whole pixel's estimate.
TEST(SpecularPeak, ACornerFarOffTheLobeDoesNotSilenceThePeak) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(-0.02f, 3.0f, -0.03f, 0.02f, c);  // the peak inside, the right corners ~70 degrees off it
  const glm::vec3 integer_exponent = hidden_highlight(f.scene, c, glm::vec3(1e-6f));
  for (SurfaceProbe& p : c) p.shininess = 10000.5f;
  const glm::vec3 fractional_exponent = hidden_highlight(f.scene, c, glm::vec3(1e-6f));
  ASSERT_GT(integer_exponent.r, 0.0f);
  EXPECT_TRUE(std::isfinite(fractional_exponent.r));
  EXPECT_NEAR(fractional_exponent.r, integer_exponent.r, 1e-3 * integer_exponent.r);
}

TEST(SpecularPeak, NothingHiddenAwayFromThePeakInShadowOrBelowVisibility) {
  const GlossyFloor f;
  SurfaceProbe c[4];
  f.corners(0.5f, 0.545f, -0.03f, 0.02f, c);  // the peak is far outside
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e-6f)), glm::vec3(0.0f));

  f.corners(-0.02f, 0.025f, -0.03f, 0.02f, c);
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e6f)), glm::vec3(0.0f));  // nothing can show
  for (SurfaceProbe& p : c) p.blocked = 1u;  // light 0 blocked at every corner
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e-3f)), glm::vec3(0.0f));
  c[0].specular = glm::vec3(0.0f);  // a corner without a highlight (or a miss): no estimate
  c[0].blocked = c[1].blocked = c[2].blocked = c[3].blocked = 0u;
  EXPECT_EQ(hidden_highlight(f.scene, c, glm::vec3(1e-3f)), glm::vec3(0.0f));
}

// A ridge across the glossy floor's peak: the normal turns by theta(u) = 0.4 u^2 about y,
// u in pixels from the ridge, so the pixel's corners (u = +-0.5) are both 0.1 rad off the
// half vector while its middle meets it, a streak along y that no corner sees. The 4 x 4
// corners around the pixel (u = -1.5 .. 1.5), row-major, with the floor's probes.
struct Ridge {
  GlossyFloor floor;
  static constexpr float kPixel = 0.01f;  // floor units per pixel
  SurfaceProbe stencil[16];
  static glm::vec3 normal(float u) {
    const float theta = 0.4f * u * u;
    return {std::sin(theta), 0.0f, std::cos(theta)};
  }
  Ridge() {
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const float u = float(i) - 1.5f, v = float(j) - 1.5f;
        SurfaceProbe& p = stencil[j * 4 + i];
        p = floor.probe({u * kPixel, v * kPixel, 0.0f});
        p.normal = normal(u);
      }
  }
  // The pixel's corners (TL at stencil[5]) and the ring around them.
  ProbeStencil view() const { return {&stencil[5], sizeof(SurfaceProbe), 4 * sizeof(SurfaceProbe)}; }
  void corners(SurfaceProbe out[4]) const { out[0] = stencil[5], out[1] = stencil[6], out[2] = stencil[9], out[3] = stencil[10]; }
  // The true mean over the pixel of the highlight (GlossyFloor::highlight with the ridge's normal).
  double true_mean(float pixel = kPixel) const {
    const int n = 400;
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      const float u = -0.5f + (float(k) + 0.5f) / float(n);
      SurfaceProbe s = floor.probe({u * pixel, 0.0f, 0.0f});
      s.normal = normal(u);
      glm::vec3 wi, scale;
      float distance;
      light_towards(floor.scene.lights[0], s.position, wi, distance, scale);
      const float cos_n = glm::dot(s.normal, wi);
      const glm::vec3 r = 2.0f * cos_n * s.normal - wi;
      const float lobe = std::pow(std::max(0.0f, glm::dot(r, s.view)), s.shininess);
      sum += 0.04f * phong_normalisation(s.shininess) * lobe * scale.r * cos_n;
    }
    return sum / n;  // constant along y (the ridge), up to the light's slow fall-off
  }
};

TEST(SpecularPeak, NormalInterpolationErrorIsTheBilinearBoundOfTheNormalsCurvature) {
  Ridge ridge;
  // theta'' = 0.8 per pixel^2: the second difference of the normals is about 0.8 along u, 0 along v.
  const float ridge_error = normal_interpolation_error(ridge.view());
  EXPECT_NEAR(ridge_error, 0.78f / 8.0f, 0.01f);
  for (SurfaceProbe& p : ridge.stencil) p.normal = glm::vec3(0.0f, 0.0f, 1.0f);  // flat
  EXPECT_EQ(normal_interpolation_error(ridge.view()), 0.0f);
  for (SurfaceProbe& p : ridge.stencil) p.normal = glm::normalize(glm::vec3(0.1f * p.position.x / Ridge::kPixel, 0.0f, 1.0f));
  EXPECT_LT(normal_interpolation_error(ridge.view()), 0.02f * ridge_error);  // a slope: nearly linear

  Ridge other;
  for (int j = 0; j < 4; ++j) other.stencil[j * 4 + 3].material = 7u;  // the last column is another surface
  for (int j = 0; j < 4; ++j) other.stencil[j * 4 + 0].material = 7u;  // and the first
  EXPECT_EQ(normal_interpolation_error(other.view()), 0.0f);  // across materials nothing counts
  Ridge dull;
  dull.stencil[10].specular = glm::vec3(0.0f);  // a corner without a highlight: no estimate at all
  EXPECT_EQ(normal_interpolation_error(dull.view()), 0.0f);
}

// Split vertex normals along a crease: the normal turns by 0.2 rad about y at u = 0, mid-way
// between the pixel's corners, and is constant on either side. The second differences at
// the two corners are equal and opposite; the normals inside the pixel lie up to half the
// step from the corners' interpolation, which the smooth bound (a quarter of that) misses.
TEST(SpecularPeak, ANormalStepBetweenTheCornersBoundsByHalfTheStep) {
  Ridge step;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const float theta = i >= 2 ? 0.2f : 0.0f;
      step.stencil[j * 4 + i].normal = {std::sin(theta), 0.0f, std::cos(theta)};
    }
  const float size = 2.0f * std::sin(0.1f);  // |n1 - n0|
  EXPECT_NEAR(normal_interpolation_error(step.view()), 0.5f * size, 1e-5f);
  // A step wider than the visibility map's angle is the map's: the smooth bound alone.
  EXPECT_NEAR(normal_interpolation_error(step.view(), 0.9f * size), size / 8.0f, 1e-5f);
  EXPECT_NEAR(normal_interpolation_error(step.view(), 1.1f * size), 0.5f * size, 1e-5f);
  // The same normals as a smooth curve (the ridge) keep the smooth bound: their second
  // differences agree in direction.
  const Ridge ridge;
  EXPECT_NEAR(normal_interpolation_error(ridge.view()), normal_interpolation_error(ridge.view(), 0.0f), 1e-7f);
  // A step just outside the pixel (between its left corner and the ring's): only that
  // corner's second difference sees it, so no step inside is inferred.
  Ridge outside;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const float theta = i >= 1 ? 0.2f : 0.0f;
      outside.stencil[j * 4 + i].normal = {std::sin(theta), 0.0f, std::cos(theta)};
    }
  EXPECT_NEAR(normal_interpolation_error(outside.view()), size / 8.0f, 1e-5f);
}

// Second differences at an edge's two ends at right angles (the normals bend one way past
// one end and another way past the other) are no step: only nearly opposite ones
// (cosine below -kStepCosine) are. The smooth bound alone, (|n_xx| + |n_yy|) / 8.
TEST(SpecularPeak, SecondDifferencesAtRightAnglesAreNoStep) {
  Ridge bent;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)  // the ring's first column tilted about x, its last about y
      bent.stencil[j * 4 + i].normal = glm::normalize(glm::vec3(i == 3 ? 0.1f : 0.0f, i == 0 ? 0.1f : 0.0f, 1.0f));
  const float along_x = glm::length(bent.stencil[4].normal - 2.0f * bent.stencil[5].normal + bent.stencil[6].normal);
  EXPECT_NEAR(normal_interpolation_error(bent.view()), along_x / 8.0f, 1e-6f);
}

// Nor are second differences at 135 degrees (cosine -0.7, above -kStepCosine = -0.9):
// an obtuse bend is still no step, only a nearly opposite one is.
TEST(SpecularPeak, SecondDifferencesAtAnObtuseAngleAreNoStep) {
  Ridge bent;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)  // the first column tilted towards +y, the last towards (+x, -y)
      bent.stencil[j * 4 + i].normal =
          glm::normalize(glm::vec3(i == 3 ? 0.0707f : 0.0f, i == 0 ? 0.1f : (i == 3 ? -0.0707f : 0.0f), 1.0f));
  const float left = glm::length(bent.stencil[4].normal - 2.0f * bent.stencil[5].normal + bent.stencil[6].normal);
  const float right = glm::length(bent.stencil[5].normal - 2.0f * bent.stencil[6].normal + bent.stencil[7].normal);
  EXPECT_NEAR(normal_interpolation_error(bent.view()), std::max(left, right) / 8.0f, 1e-6f);
}

// The cheap curvature test widens the corners' spread of half vectors by the normals'
// interpolation error on either side, 2 e: four equal corners (spread 0) whose ring bends
// the normals (e = 0.0125 from the second differences) keep a light whose s (2 e)^2 / 2
// error reaches `visible` (s e^2 / 2 would not), and the grid's estimate finds what the
// corners miss.
TEST(SpecularPeak, TheCurvatureTestWidensTheSpreadByTheNormalErrorOnBothSides) {
  Ridge bent;
  const float shininess = 3840.0f;  // s e^2 / 2 = 0.3, s (2 e)^2 / 2 = 1.2
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      SurfaceProbe& p = bent.stencil[j * 4 + i];
      p = bent.floor.probe({0.01f, 0.0f, 0.0f});
      p.shininess = shininess;
      if (i == 0 || i == 3) p.normal = glm::normalize(glm::vec3(0.0f, 0.1f, 1.0f));  // the ring's columns bend alike
    }
  SurfaceProbe c[4];
  bent.corners(c);
  const ProbeStencil view = bent.view();
  const float e = normal_interpolation_error(view);
  ASSERT_NEAR(e, 0.0125f, 1e-4f);
  glm::vec3 wi, scale;
  float distance;
  light_towards(bent.floor.scene.lights[0], c[0].position, wi, distance, scale);
  const glm::vec3 amplitude = c[0].specular * phong_normalisation(shininess) * scale * glm::dot(c[0].normal, wi);
  EXPECT_GT(hidden_highlight(bent.floor.scene, c, 0.6f * amplitude, &view).r, 0.0f);
}

TEST(SpecularPeak, AStreakOnARidgeBetweenTheCornersIsFound) {
  const Ridge ridge;
  SurfaceProbe c[4];
  ridge.corners(c);
  const double truth = ridge.true_mean();
  const glm::vec3 visible(0.05f * float(truth));
  // The bilinear model alone sees corners 0.1 rad off the peak everywhere: nothing.
  EXPECT_EQ(hidden_highlight(ridge.floor.scene, c, visible), glm::vec3(0.0f));
  // Widened by the normals' curvature it finds the streak, at least as bright as it is.
  const ProbeStencil view = ridge.view();
  const glm::vec3 found = hidden_highlight(ridge.floor.scene, c, visible, &view);
  EXPECT_GE(found.r, 0.5 * truth);
}

// The same ridge on pixels six times as wide: the corners' half vectors spread so far that
// the lobe is narrow against the pixel, and the hull of their d misses the peak by less
// than the normals' interpolation bound; widened by it, the hull's distance is 0. (The
// narrow model spreads a point's integral over the pixel, so it finds the streak, a line,
// at under half its brightness.)
TEST(SpecularPeak, AStreakOnARidgeAcrossAWidePixelIsFound) {
  Ridge ridge;
  const float pixel = 6.0f * Ridge::kPixel;
  for (SurfaceProbe& p : ridge.stencil) {
    const glm::vec3 n = p.normal;
    p = ridge.floor.probe(6.0f * p.position);
    p.normal = n;
  }
  SurfaceProbe c[4];
  ridge.corners(c);
  const double truth = ridge.true_mean(pixel);
  const glm::vec3 visible(0.05f * float(truth));
  EXPECT_EQ(hidden_highlight(ridge.floor.scene, c, visible), glm::vec3(0.0f));
  const ProbeStencil view = ridge.view();
  EXPECT_GE(hidden_highlight(ridge.floor.scene, c, visible, &view).r, 0.25 * truth);
}

// Pixel (20, 20)'s red radiance in a size x size frame, adaptive with the highlight flag
// off and on, and the 25-point lattice, with the adaptive runs' stats.
struct PeakPixel {
  float off, on, lattice;
  int on_rays = 0;  // the pixel's rays with the flag on
  RenderStats off_stats, on_stats;
};
PeakPixel render_peak_pixel(const Shader& shader, const Camera& camera, int size) {
  int rays = 0;
  auto render = [&](AaMode aa, bool highlights, RenderStats& stats) {
    RenderSettings r;
    r.width = r.height = size;
    r.aa = aa;
    r.uniform = {UniformPattern::Lattice, 25};
    r.adaptive.highlights = highlights;
    Film film;
    render_frame(shader, camera, GeoMap{}, r, film, stats);
    rays = film.rays[size_t(20) * size + 20];
    return film.radiance[size_t(20) * size + 20].r;
  };
  PeakPixel p;
  RenderStats lattice_stats;
  p.off = render(AaMode::Adaptive, false, p.off_stats);
  p.on = render(AaMode::Adaptive, true, p.on_stats);
  p.on_rays = rays;
  p.lattice = render(AaMode::Uniform, false, lattice_stats);
  return p;
}

// A glossy floor seen from above, its light at z = 2 placed so that the mirror point is
// the centre of pixel (20, 20), where none of the corners sees it, seen through whatever
// `s` adds between the camera and the floor: found all the same, the pixel refined to the
// lattice's value and at most its neighbours flagged.
void expect_hidden_peak_found(Scene s) {
  const int size = 40;
  const CameraRays camera(s.cameras[0], size, size);
  const glm::vec3 dir = camera.direction(20.5f, 20.5f);
  const glm::vec3 p = camera.origin - dir * (camera.origin.z / dir.z);
  const glm::vec3 back = camera.origin - p;
  s.lights[0].position = p + glm::vec3(-back.x, -back.y, back.z) * 0.5f;
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  const PeakPixel px = render_peak_pixel(shader, s.cameras[0], size);
  EXPECT_EQ(px.off_stats.aa.hidden_pixels, 0u);
  EXPECT_GE(px.on_stats.aa.hidden_pixels, 1u);
  EXPECT_LE(px.on_stats.aa.hidden_pixels, 4u);             // the peak's pixel and at most its neighbours
  EXPECT_GT(px.lattice, 2.0f * px.off);                     // the corners alone miss most of it
  EXPECT_NEAR(px.on, px.lattice, 0.05f * px.lattice);       // refined: the lattice's 25 points
}

// Through the renderer: the floor's pinpoint highlight in plain view.
TEST(SpecularPeak, RendererRefinesThePixelWithThePinpointHighlight) {
  Scene s = test::lit_floor(0.3f, 1.0f, 2.0f);
  s.materials[0].roughness = 0.0f;  // Phong exponent 10000
  s.finalize_materials();
  expect_hidden_peak_found(s);
}

// The same pinpoint highlight seen in a mirror: a mirror floor at z = 0 and a glossy
// ceiling at z = 5 facing down, the camera between them looking down, the light placed
// so that the ceiling's highlight, seen in the mirror, peaks at the centre of pixel
// (20, 20). Unfolded, the ceiling is a floor at z = -5 seen through the mirror plane.
TEST(SpecularPeak, RendererRefinesAHighlightSeenInAMirror) {
  Scene s;
  const Material mirror = test::mirror_material(glm::vec3(0.9f));
  Material gloss = test::diffuse_material(glm::vec3(0.3f));
  gloss.roughness = 0.0f;  // Phong exponent 10000
  s.materials = {mirror, gloss};
  test::add_quad(s, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  test::add_quad(s, {-10, -10, 5}, {-10, 10, 5}, {10, 10, 5}, {10, -10, 5}, 1);  // faces -z
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.max_depth = 1;
  const int size = 40;
  const CameraRays camera(s.cameras[0], size, size);
  const glm::vec3 dir = camera.direction(20.5f, 20.5f);
  const glm::vec3 p = camera.origin - dir * ((camera.origin.z + 5.0f) / dir.z);  // on the unfolded ceiling
  const glm::vec3 back = camera.origin - p;
  const glm::vec3 unfolded_light = p + glm::vec3(-back.x, -back.y, back.z) * 0.5f;
  Light light;
  light.position = {unfolded_light.x, unfolded_light.y, -unfolded_light.z};  // between the mirror and the ceiling
  light.intensity = glm::vec3(1.0f);
  s.lights.push_back(light);
  s.finalize_materials();
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);

  // The corner probes: the mirror, and the ceiling seen in it, its highlight scaled by
  // the mirror's reflectance.
  const SceneSource::Probe probe = centre_probe(shader, camera);
  const SurfaceProbe& ceiling = probe.node[probe_slot(reflected_node(0))];
  EXPECT_EQ(probe.surface().material, 0u);
  EXPECT_EQ(ceiling.material, 1u);
  EXPECT_NEAR(ceiling.position.z, 5.0f, 1e-4f);
  EXPECT_NEAR(ceiling.specular.r, s.whitted[1].specular.r * 0.9f, 1e-3f * s.whitted[1].specular.r);
  EXPECT_EQ(probe.node[probe_slot(refracted_node(0))].specular, glm::vec3(0.0f));  // no glass

  const PeakPixel px = render_peak_pixel(shader, s.cameras[0], size);
  const float off = px.off, on = px.on, lattice = px.lattice;
  const RenderStats &off_stats = px.off_stats, &on_stats = px.on_stats;
  EXPECT_EQ(off_stats.aa.hidden_pixels, 0u);  // the flag off: nothing flagged
  EXPECT_GE(on_stats.aa.hidden_pixels, 1u);
  EXPECT_GT(lattice, 2.0f * off);             // the corners alone miss most of it
  EXPECT_NEAR(on, lattice, 0.05f * lattice);  // refined: the lattice's 25 points
}

// Through glass: the refracted ray's first hit is probed, its highlight scaled by the
// transmitted share (1 - Fresnel) x transmission; the Fresnel reflection's too.
TEST(SpecularPeak, ProbesSeeThroughGlass) {
  Scene s = test::lit_floor(0.3f, 1.0f, 2.0f);
  s.materials[0].roughness = 0.0f;
  s.materials.push_back(test::glass_material(1.5f));
  test::add_quad(s, {-10, -10, 3}, {10, -10, 3}, {10, 10, 3}, {-10, 10, 3}, 1);  // above the light  // a pane facing the camera
  s.finalize_materials();
  const SceneSource::Probe probe = centre_probe(s);  // straight down: normal incidence
  const float fresnel = 0.04f;  // ((1.5 - 1) / (1.5 + 1))^2
  EXPECT_EQ(probe.surface().material, 1u);
  EXPECT_EQ(probe.node[probe_slot(refracted_node(0))].material, 0u);
  EXPECT_NEAR(probe.node[probe_slot(refracted_node(0))].position.z, 0.0f, 1e-4f);
  EXPECT_NEAR(probe.node[probe_slot(refracted_node(0))].specular.r, s.whitted[0].specular.r * (1.0f - fresnel), 1e-3f);
  EXPECT_EQ(probe.node[probe_slot(reflected_node(0))].specular, glm::vec3(0.0f));  // the reflection sees the sky
}

// Down the reflection's branch of the path tree: a mirror floor reflects a glass pane, which
// reflects the floor again (node 3) and shows a glossy ceiling through it (node 4); each
// probe's highlight is scaled by every weight on its path from the camera.
TEST(SpecularPeak, ProbesFollowTheReflectionsBranchOfThePathTree) {
  Scene s;
  const Material mirror = test::mirror_material(glm::vec3(0.9f));
  Material gloss = test::diffuse_material(glm::vec3(0.3f));
  gloss.roughness = 0.0f;
  s.materials = {mirror, test::glass_material(1.5f), gloss};
  test::add_quad(s, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);  // faces +z
  test::add_quad(s, {-10, -10, 5}, {-10, 10, 5}, {10, 10, 5}, {10, -10, 5}, 1);  // faces -z
  test::add_quad(s, {-10, -10, 6}, {-10, 10, 6}, {10, 10, 6}, {10, -10, 6}, 2);  // faces -z
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  Light light;
  light.position = {1, 1, 3};
  s.lights.push_back(light);
  s.max_depth = 3;
  s.finalize_materials();
  const SceneSource::Probe probe = centre_probe(s);  // straight down: normal incidence
  const float mirror_share = 0.9f, fresnel = 0.04f;  // the pane: ((1.5 - 1) / (1.5 + 1))^2
  const SurfaceProbe& pane = probe.node[probe_slot(reflected_node(0))];
  const SurfaceProbe& floor_again = probe.node[probe_slot(reflected_node(reflected_node(0)))];
  const SurfaceProbe& ceiling = probe.node[probe_slot(refracted_node(reflected_node(0)))];
  EXPECT_EQ(probe.surface().material, 0u);
  EXPECT_EQ(probe.node[probe_slot(refracted_node(0))].specular, glm::vec3(0.0f));  // a mirror refracts nothing
  EXPECT_EQ(pane.material, 1u);
  EXPECT_NEAR(pane.position.z, 5.0f, 1e-4f);
  EXPECT_EQ(floor_again.material, 0u);
  EXPECT_NEAR(floor_again.position.z, 0.0f, 1e-4f);
  EXPECT_NEAR(floor_again.view.z, 1.0f, 1e-4f);  // back along the ray that reached it
  EXPECT_NEAR(floor_again.specular.r, s.whitted[0].specular.r * mirror_share * fresnel, 1e-3f * s.whitted[0].specular.r);
  EXPECT_EQ(ceiling.material, 2u);
  EXPECT_NEAR(ceiling.position.z, 6.0f, 1e-4f);
  EXPECT_NEAR(ceiling.specular.r, s.whitted[2].specular.r * mirror_share * (1.0f - fresnel),
              1e-3f * s.whitted[2].specular.r);
  // The word the flag reads instead of every node's record says which nodes have a highlight.
  for (int k = 0; k < kProbeNodes; ++k)
    EXPECT_EQ((probe.highlit >> k) & 1u, uint32_t(has_highlight(probe.node[k]))) << "slot " << k;
  EXPECT_NE(probe.highlit & (1u << probe_slot(refracted_node(reflected_node(0)))), 0u);  // the ceiling
  EXPECT_EQ(probe.highlit & (1u << probe_slot(refracted_node(0))), 0u);                  // none
}

// The probed nodes fill the slots 0 .. kProbeNodes - 1, each once, and form a subtree: a
// path the flag follows is followed from the camera on (the shader stops at the first
// node not probed).
TEST(SpecularPeak, ProbeSlotsNumberASubtreeOfThePathTree) {
  std::vector<int> nodes_in_slot(kProbeNodes, -1);
  for (int k = 0; k < kPathTreeNodes; ++k) {
    if (!probed(k)) continue;
    ASSERT_LT(probe_slot(k), kProbeNodes);
    EXPECT_EQ(nodes_in_slot[size_t(probe_slot(k))], -1) << "slot " << probe_slot(k) << " taken twice";
    nodes_in_slot[size_t(probe_slot(k))] = k;
    if (k > 0) {
      EXPECT_TRUE(probed((k - 1) / 2)) << "node " << k << "'s parent is not probed";
    }
  }
  for (int slot = 0; slot < kProbeNodes; ++slot) EXPECT_GE(nodes_in_slot[size_t(slot)], 0) << "slot " << slot;
  EXPECT_FALSE(probed(-1));
  EXPECT_FALSE(probed(kPathTreeNodes));
  // What the docs say is followed: the reflection's reflection and refraction, and the
  // refraction's subtree to depth 3.
  for (int k : {0, 1, 2, 3, 4, 5, 6, 11, 12, 13, 14}) EXPECT_TRUE(probed(k)) << k;
  for (int k : {7, 8, 9, 10}) EXPECT_FALSE(probed(k)) << k;
}

// Three glass panes above a glossy floor: seen straight down, the floor is the third
// refraction's hit (node 14), its highlight scaled by the three transmitted shares.
TEST(SpecularPeak, ProbesSeeThroughThreePanes) {
  Scene s = test::lit_floor(0.3f, 1.0f, 3.5f);
  s.materials[0].roughness = 0.0f;
  s.materials.push_back(test::glass_material(1.5f));
  for (float z : {1.0f, 2.0f, 3.0f}) test::add_quad(s, {-10, -10, z}, {10, -10, z}, {10, 10, z}, {-10, 10, z}, 1);
  s.max_depth = 3;
  s.finalize_materials();
  const SceneSource::Probe probe = centre_probe(s);
  const int third = refracted_node(refracted_node(refracted_node(0)));
  ASSERT_EQ(third, 14);
  const SurfaceProbe& floor = probe.node[probe_slot(third)];
  EXPECT_EQ(floor.material, 0u);
  EXPECT_NEAR(floor.position.z, 0.0f, 1e-4f);
  EXPECT_NEAR(floor.view.z, 1.0f, 1e-3f);
  // Each pane passes 1 - F of what reaches it; F at normal incidence for eta = 1.5 or
  // 1 / 1.5 alike.
  const float transmitted = std::pow(1.0f - 0.04f, 3.0f);
  EXPECT_NEAR(floor.specular.r, s.whitted[0].specular.r * transmitted, 1e-2f * s.whitted[0].specular.r);
  EXPECT_EQ(probe.node[probe_slot(refracted_node(refracted_node(0)))].material, 1u);  // the middle pane
}

// Three panes of glass whose index is 1 (they bend nothing, so the mirror point stays where
// it was), the light between them: the highlight is four surfaces from the camera.
TEST(SpecularPeak, RendererRefinesAHighlightSeenThroughThreePanes) {
  Scene s = test::lit_floor(0.3f, 1.0f, 2.0f);
  s.materials[0].roughness = 0.0f;
  s.materials.push_back(test::glass_material(1.0f));
  s.materials.back().roughness = 1.0f;  // no pinpoint highlights of their own
  for (float z : {0.5f, 1.0f, 3.0f}) test::add_quad(s, {-10, -10, z}, {10, -10, z}, {10, 10, z}, {-10, 10, z}, 1);
  s.max_depth = 3;
  s.finalize_materials();
  expect_hidden_peak_found(s);
}

// The glossy floor with a BLEND pane (alpha 0.3, as the vase's) filling the plane z =
// `pane_z`; the pane has no highlight of its own.
Scene floor_under_a_blend_pane(float pane_z) {
  Scene s = test::lit_floor(0.3f, 1.0f, 2.0f);
  s.materials[0].roughness = 0.0f;
  Material pane = test::diffuse_material(glm::vec3(0.5f));
  pane.alpha_mode = AlphaMode::Blend;
  pane.base_alpha = 0.3f;
  pane.roughness = 1.0f;
  s.materials.push_back(pane);
  test::add_quad(s, {-10, -10, pane_z}, {10, -10, pane_z}, {10, 10, pane_z}, {-10, 10, pane_z}, 1);
  s.finalize_materials();
  return s;
}

// The pane between the camera and the light (z = 2): only a probe of what lies behind the
// pane can see the floor's highlight; the pane passes 70 % of it.
TEST(SpecularPeak, RendererRefinesAHighlightSeenThroughABlendPane) {
  expect_hidden_peak_found(floor_under_a_blend_pane(3.0f));
}

// The pane below the light: the floor is lit through it at every corner, 70 % of the light,
// and seen through it. A light counted as shadowed wherever its shadow rays were dimmed
// would not be examined, and the peak would go unseen.
TEST(SpecularPeak, RendererRefinesAHighlightLitThroughABlendPane) {
  expect_hidden_peak_found(floor_under_a_blend_pane(1.5f));
}

// What a probe sees through a BLEND pane carries the share the pane passes, 1 - alpha
// (0.7 here), not alpha.
TEST(SpecularPeak, ProbesThroughABlendPaneCarryTheShareItPasses) {
  const Scene s = floor_under_a_blend_pane(3.0f);
  const SceneSource::Probe probe = centre_probe(s);
  EXPECT_EQ(probe.surface().material, 1u);
  const SurfaceProbe& floor = probe.node[probe_slot(refracted_node(0))];
  EXPECT_EQ(floor.material, 0u);
  EXPECT_NEAR(floor.position.z, 0.0f, 1e-4f);
  EXPECT_NEAR(floor.specular.r, s.whitted[0].specular.r * 0.7f, 1e-5f * s.whitted[0].specular.r);
}

}  // namespace
}  // namespace zz
