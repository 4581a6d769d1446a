#include "render/specular_peak.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "aa/lattice.h"
#include "core/simd.h"
#include "render/lighting.h"
#include "render/lighting4.h"
#include "render/texture_range.h"
#include "scene/scene.h"

namespace zz {

namespace {

constexpr float kPi = 3.14159265f;
constexpr int kGrid = 4;  // per axis, the wide lobe's quadrature over the pixel

float cross2(glm::vec2 a, glm::vec2 b) { return a.x * b.y - a.y * b.x; }

// The origin inside (or on) the non-degenerate triangle abc.
bool origin_in_triangle(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
  if (cross2(b - a, c - a) == 0.0f) return false;  // degenerate: the segments decide
  const float d1 = cross2(b - a, -a), d2 = cross2(c - b, -b), d3 = cross2(a - c, -c);
  const bool negative = d1 < 0.0f || d2 < 0.0f || d3 < 0.0f, positive = d1 > 0.0f || d2 > 0.0f || d3 > 0.0f;
  return !(negative && positive);
}

float origin_distance_to_segment(glm::vec2 a, glm::vec2 b) {
  const glm::vec2 ab = b - a;
  const float len2 = glm::dot(ab, ab);
  const float t = len2 > 0.0f ? std::clamp(-glm::dot(a, ab) / len2, 0.0f, 1.0f) : 0.0f;
  return glm::length(a + t * ab);
}

// Any unit vector orthogonal to unit n (which one does not matter: the pixel's four
// corners are projected on the same frame).
glm::vec3 orthogonal(glm::vec3 n) {
  const glm::vec3 axis = std::fabs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
  return glm::normalize(glm::cross(n, axis));
}

// The physical lattice points (bit p: aa/lattice.h's P_p) at which a lobe of `shininess`
// and `amplitude`, peaking where the bilinear patch of d (TL, TR, BL, BR) is 0, may reach
// `visible` x 25 / 4: its bound at |d| less the normals' interpolation bound. A zone is
// 4 of the pixel's 25 points, so a zone none of whose points reaches that holds less than
// `visible` of the pixel's mean. None reaching it, the point nearest the peak (a lobe
// narrower than the lattice's spacing between its points).
uint32_t lattice_points_lit(const glm::vec2 d[4], float normal_error, float shininess, glm::vec3 amplitude,
                            glm::vec3 visible) {
  const glm::vec3 zone_visible = visible * (float(kLatticePoints) / 4.0f);
  uint32_t lit = 0;
  int nearest = 0;
  float nearest_distance = std::numeric_limits<float>::infinity();
  for (int p = 0; p < kLatticePoints; ++p) {
    const float u = kLattice[size_t(p)].u, v = kLattice[size_t(p)].v;
    const glm::vec2 q = (1.0f - v) * ((1.0f - u) * d[0] + u * d[1]) + v * ((1.0f - u) * d[2] + u * d[3]);
    const float distance = std::max(0.0f, glm::length(q) - normal_error);
    if (distance < nearest_distance) nearest_distance = distance, nearest = p;
    if (glm::any(glm::greaterThanEqual(amplitude * lobe_bound(distance, shininess), zone_visible))) lit |= 1u << p;
  }
  return lit ? lit : 1u << nearest;
}

// One light's terms at the pixel's four corners, the corners in SSE lanes (light_towards4,
// bit-identical to light_towards corner by corner): the cosine at the normal (0 where
// unlit), d = n - h (h from the direction light_towards gives, else the normal) and the
// light's radiance scale. One division or square root serves four corners.
void corner_light_terms(const Light& light, const SurfaceProbe c[4], glm::vec3 d3[4], float cos_n[4],
                        glm::vec3 scale[4]) {
  auto lanes = [&](auto member) {
    alignas(16) float x[4], y[4], z[4];
    for (int k = 0; k < 4; ++k) {
      const glm::vec3& a = c[k].*member;
      x[k] = a.x, y[k] = a.y, z[k] = a.z;
    }
    return vec3x4{float4::load(x), float4::load(y), float4::load(z)};
  };
  const vec3x4 n = lanes(&SurfaceProbe::normal), view = lanes(&SurfaceProbe::view);
  const LightSample4 s = light_towards4(light, LightConstants(light), lanes(&SurfaceProbe::position));
  const vec3x4 wi = select(s.towards, s.to_light, n);
  const float4 cos = select(s.lit, dot(n, wi), float4(0.0f));
  const vec3x4 h = wi + view;
  const vec3x4 dn = n - h * (float4(1.0f) / sqrt(dot(h, h)));  // glm::normalize's v * (1 / |v|)
  alignas(16) float out[7][4];
  cos.store(out[0]);
  dn.x.store(out[1]), dn.y.store(out[2]), dn.z.store(out[3]);
  s.scale.x.store(out[4]), s.scale.y.store(out[5]), s.scale.z.store(out[6]);
  for (int k = 0; k < 4; ++k) {
    cos_n[k] = out[0][k];
    d3[k] = {out[1][k], out[2][k], out[3][k]};
    scale[k] = {out[4][k], out[5][k], out[6][k]};
  }
}

}  // namespace

// The Phong lobe where |n - h| = distance: |n - h| = 2 sin(theta / 2), and the mirror
// direction turns by 2 theta.
float lobe_at(float distance, float shininess) {
  const float theta = 2.0f * std::asin(std::min(1.0f, 0.5f * distance));
  return std::pow(std::max(0.0f, std::cos(std::min(2.0f * theta, 0.5f * kPi))), shininess);  // cosf(pi / 2) < 0
}

// An upper bound of lobe_at: 2 theta = 4 asin(d / 2) >= 2 d, and cos x <= exp(-x^2 / 2) on
// [0, pi / 2], so the lobe is at most exp(-2 s d^2); and a little more for lobe_at's float
// rounding: its cosine near 1 may be up to an ulp (1.2e-7) high, which the power s raises
// to a factor exp(1.2e-7 s).
float lobe_bound(float distance, float shininess) {
  return 1.0001f * std::exp(shininess * (1.2e-7f - 2.0f * distance * distance));
}

float origin_distance_to_hull(const glm::vec2 p[4]) {
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(p[k].x) || !std::isfinite(p[k].y)) return std::numeric_limits<float>::infinity();
  // The two triangulations of four points together cover their convex hull.
  if (origin_in_triangle(p[0], p[1], p[2]) || origin_in_triangle(p[0], p[1], p[3]) ||
      origin_in_triangle(p[0], p[2], p[3]) || origin_in_triangle(p[1], p[2], p[3]))
    return 0.0f;
  float d = std::numeric_limits<float>::infinity();  // the hull's edges are among the six pairs
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) d = std::min(d, origin_distance_to_segment(p[i], p[j]));
  return d;
}

float bilinear_quad_area(const glm::vec2 p[4]) {
  return 0.5f * std::fabs(cross2(p[0], p[1]) + cross2(p[1], p[3]) + cross2(p[3], p[2]) + cross2(p[2], p[0]));
}

float normal_interpolation_error(const ProbeStencil& stencil, float step_limit) {
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
      if (!has_highlight(stencil.at(i, j))) return 0.0f;
  // Second differences along x and y at corner (i, j) of the pixel.
  glm::vec3 along_x[2][2], along_y[2][2];
  float nxx = 0.0f, nyy = 0.0f;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const SurfaceProbe& c = stencil.at(i, j);
      auto second_difference = [&c](const SurfaceProbe& a, const SurfaceProbe& b) {
        if (a.material != c.material || b.material != c.material || !has_highlight(a) || !has_highlight(b))
          return glm::vec3(0.0f);
        return a.normal - 2.0f * c.normal + b.normal;
      };
      along_x[j][i] = second_difference(stencil.at(i - 1, j), stencil.at(i + 1, j));
      along_y[j][i] = second_difference(stencil.at(i, j - 1), stencil.at(i, j + 1));
      nxx = std::max(nxx, glm::length(along_x[j][i]));
      nyy = std::max(nyy, glm::length(along_y[j][i]));
    }
  // A step between corners a and b: f(a-1) - 2 f(a) + f(b) = step = -(f(a) - 2 f(b) + f(b+1)).
  auto step_between = [step_limit](glm::vec3 at_a, glm::vec3 at_b) {
    const float la = glm::length(at_a), lb = glm::length(at_b);
    if (!(glm::dot(at_a, at_b) < -kStepCosine * la * lb)) return 0.0f;
    const float step = 0.5f * (la + lb);
    return step <= step_limit ? step : 0.0f;
  };
  const float step_x = std::max(step_between(along_x[0][0], along_x[0][1]), step_between(along_x[1][0], along_x[1][1]));
  const float step_y = std::max(step_between(along_y[0][0], along_y[1][0]), step_between(along_y[0][1], along_y[1][1]));
  return std::max((nxx + nyy) * 0.125f, 0.5f * (step_x + step_y));
}

glm::vec3 hidden_highlight(const Scene& scene, const SurfaceProbe c[4], glm::vec3 visible,
                           const ProbeStencil* stencil, float step_limit,
                           const std::vector<TextureSpread>* normal_spreads, uint32_t* points) {
  float shininess = 0.0f, most_shiny = 0.0f;
  glm::vec3 specular(0.0f), most_specular(0.0f);
  for (int k = 0; k < 4; ++k) {
    if (!has_highlight(c[k])) return glm::vec3(0.0f);
    shininess += c[k].shininess;
    specular += c[k].specular;
    most_shiny = std::max(most_shiny, c[k].shininess);
    most_specular = glm::max(most_specular, c[k].specular);
  }
  shininess *= 0.25f;
  specular *= 0.25f;
  // The largest highlight any light can make here is its peak, amplitude x 1.
  const glm::vec3 largest_peak = most_specular * phong_normalisation(most_shiny);
  const float lobe_integral = kPi / (2.0f * shininess);  // of exp(-2 s |d|^2) over the plane
  const uint32_t blocked_everywhere = c[0].blocked & c[1].blocked & c[2].blocked & c[3].blocked;

  // The pixel's hit points lie within `extent` of corner 0's.
  float extent = 0.0f;
  for (int k = 1; k < 4; ++k) extent = std::max(extent, glm::length(c[k].position - c[0].position));

  float normal_error = -1.0f;  // < 0: not computed yet
  glm::vec3 hidden(0.0f);
  for (size_t l = 0; l < scene.lights.size(); ++l) {
    if ((blocked_everywhere >> (l % 32)) & 1u) continue;
    // The light's largest incident factor in the pixel, before 4 corners' worth of work: its
    // intensity, over d^2 at the nearest point of the ball around corner 0 that holds the
    // pixel's hit points (a range window and a spot cone only lower it).
    const Light& light = scene.lights[l];
    if (light.type == Light::Type::Directional) {
      if (glm::all(glm::lessThan(largest_peak * light.intensity, visible))) continue;
    } else {
      const float nearest = glm::length(light.position - c[0].position) - extent;
      if (nearest > 0.0f &&
          glm::all(glm::lessThan(largest_peak * light.intensity / (nearest * nearest), visible)))
        continue;
    }
    glm::vec3 d3[4], scale[4], incident(0.0f), strongest(0.0f);
    float cos_n[4];
    corner_light_terms(light, c, d3, cos_n, scale);
    for (int k = 0; k < 4; ++k) {
      if (!(cos_n[k] > 0.0f)) continue;
      incident += scale[k] * cos_n[k];
      strongest = glm::max(strongest, scale[k] * cos_n[k]);
    }
    const glm::vec3 amplitude = specular * phong_normalisation(shininess) * strongest;
    if (glm::all(glm::lessThan(amplitude, visible))) continue;
    // Cheap bounds before the hull: the pixel's d values lie within `span` of each corner's
    // (the corners' own spread, and the normals' curvature on either side).
    float span2 = 0.0f, nearest = std::numeric_limits<float>::infinity();
    for (int k = 0; k < 4; ++k) {
      nearest = std::min(nearest, glm::length(d3[k]));
      for (int j = k + 1; j < 4; ++j) span2 = std::max(span2, glm::dot(d3[k] - d3[j], d3[k] - d3[j]));
    }
    if (!std::isfinite(nearest) || !std::isfinite(span2)) continue;
    if (normal_error < 0.0f)
      normal_error = (stencil ? normal_interpolation_error(*stencil, step_limit) : 0.0f) +
                     (normal_spreads ? normal_map_spread(scene, *normal_spreads, c) : 0.0f);
    const float span = std::sqrt(span2) + 2.0f * normal_error;
    span2 = span * span;
    // The lobe exp(-2 s theta^2) has |f''| <= 4 s, so where it is wide against the pixel the
    // corners' mean is within s span^2 / 2 of the true mean.
    if (glm::all(glm::lessThan(amplitude * (0.5f * shininess * span2), visible))) continue;
    // Nowhere in the pixel closer to the peak than `nearest - span`; the Gaussian bound
    // first, which decides most lights for one exp.
    const float closest = std::max(0.0f, nearest - span);
    if (glm::all(glm::lessThan(amplitude * lobe_bound(closest, shininess), visible))) continue;
    if (glm::all(glm::lessThan(amplitude * lobe_at(closest, shininess), visible))) continue;

    incident *= 0.25f;

    // d = n - h on the plane orthogonal to the mean half vector.
    const glm::vec3 mean_half = glm::normalize(c[0].normal + c[1].normal + c[2].normal + c[3].normal -
                                               (d3[0] + d3[1] + d3[2] + d3[3]));
    const glm::vec3 t1 = orthogonal(mean_half), t2 = glm::cross(mean_half, t1);
    glm::vec2 d[4];
    float corner_lobe = 0.0f;
    for (int k = 0; k < 4; ++k) {
      d[k] = {glm::dot(d3[k], t1), glm::dot(d3[k], t2)};
      corner_lobe += cos_n[k] > 0.0f ? 0.25f * lobe_at(glm::length(d[k]), shininess) : 0.0f;
    }
    const float area = bilinear_quad_area(d);
    float mean_lobe;
    if (shininess * area < float(kGrid * kGrid) / 4.0f) {
      // The lobe is wider than the grid's spacing (its sigma^2 = 1 / 4s): its mean over the
      // pixel is the mean over a kGrid x kGrid grid of the bilinear patch.
      mean_lobe = 0.0f;
      for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
          const float u = (float(i) + 0.5f) / float(kGrid), v = (float(j) + 0.5f) / float(kGrid);
          const glm::vec2 q = (1.0f - v) * ((1.0f - u) * d[0] + u * d[1]) + v * ((1.0f - u) * d[2] + u * d[3]);
          mean_lobe += lobe_at(std::max(0.0f, glm::length(q) - normal_error), shininess);
        }
      mean_lobe /= float(kGrid * kGrid);
    } else {
      // Narrow: all of the lobe's integral, pi / 2s, that falls inside the pixel, spread over it.
      const float hull_distance = origin_distance_to_hull(d);
      if (!std::isfinite(hull_distance)) continue;
      const float distance = std::max(0.0f, hull_distance - normal_error);
      const float tail = distance == 0.0f ? 1.0f : 0.5f * std::erfc(distance * std::sqrt(2.0f * shininess));
      mean_lobe = std::min(lobe_at(distance, shininess), lobe_integral * tail / area);
    }
    const float missed = mean_lobe - corner_lobe;
    if (!(missed > 0.0f)) continue;
    hidden += specular * incident * (phong_normalisation(shininess) * missed);
    if (points) *points |= lattice_points_lit(d, normal_error, shininess, amplitude, visible);
  }
  return hidden;
}

}  // namespace zz
