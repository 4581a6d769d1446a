// The analytic highlight flag (ALGORITHM.md §11, our extension of the paper): how much
// highlight radiance a pixel may hold that none of its four corner rays saw.
//
// A normalised-Phong highlight peaks where the shading normal n equals the half vector
// h = normalize(wi + wo). Over one pixel both vary smoothly, so d = n - h is close to the
// bilinear interpolation of its four corner values, projected on the plane orthogonal to
// the mean h. The peak lies inside the pixel when the origin lies inside the convex hull
// of the four projected d; otherwise the largest lobe value the pixel can reach is at the
// hull's distance from the origin. With the lobe cos^s(2 theta) ~ exp(-2 s |d|^2), whose
// integral over the d plane is pi / (2 s), a lobe narrower than the pixel has a mean of
// at most
//   min(peak, pi / (2 s) / area(hull) x tail),
// where tail = 1 with the origin inside and the Gaussian tail beyond the hull's distance
// otherwise; a wider one is averaged over a 4 x 4 grid of the bilinear patch. What the
// pixel may hold beyond its corners' mean lobe, times the light's Phong amplitude, summed
// over lights that reach at least one corner, is returned.
// The bilinear model fails where the normal field curves within a pixel: across a thin
// cylinder the normal peaks between two corners that both lie off the ridge, and its
// highlight is a streak no corner sees. The bilinear patch's interpolation error,
// |f - I f| <= (|f_xx| + |f_yy|) / 8 on the unit square, bounds that miss; the second
// derivatives are estimated by second differences of the corners' normals with the
// neighbouring corners, and the hull is widened by the bound.
// That bound assumes smooth normals. Where the shading normal steps between two corners
// (split vertex normals along a crease, a bevel thinner than a pixel), the second
// differences at the two corners point in opposite directions, and the normals inside
// the pixel may lie up to half the step from the interpolation (a step at mid-pixel): the
// bound is then the larger of the two. Steps wider than the visibility map's normal angle
// are left to the map, which flags such creases as geometric edges.
// Decided from geometry, so a pinpoint highlight between the corners is found whatever
// its size; like the visibility map it only sends rays, it never colours a pixel.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace zz {

struct Scene;
class TextureSpread;

// What the highlight test needs of a camera ray's first hit.
struct SurfaceProbe {
  glm::vec3 position{0.0f};  // the hit point
  glm::vec3 normal{0.0f};    // shading normal, turned towards the camera
  glm::vec3 view{0.0f};      // unit direction back to the camera
  glm::vec3 specular{0.0f};  // Phong highlight colour; 0 where there is no highlight (a miss)
  float shininess = 1.0f;    // Phong exponent
  // Bit l % 32: light l's shadow ray passed nothing. A light dimmed by a pane or glass on
  // its way still makes a highlight here, so it is not counted.
  uint32_t blocked = 0;
  uint32_t material = ~0u;   // index of the material hit; ~0 on a miss
  glm::vec2 uv0{0.0f}, uv1{0.0f};  // texture coordinates (TEXCOORD_0, _1) of the hit
};

// A pixel's corner probes and their neighbours in a grid whose elements hold a
// SurfaceProbe `step` bytes apart along a row and `row` bytes apart down a column (the
// probes may be members of larger per-corner records). at(0, 0) is the pixel's TL corner.
struct ProbeStencil {
  const std::byte* tl = nullptr;
  ptrdiff_t step = 0, row = 0;
  ProbeStencil(const SurfaceProbe* top_left, ptrdiff_t step_bytes, ptrdiff_t row_bytes)
      : tl(reinterpret_cast<const std::byte*>(top_left)), step(step_bytes), row(row_bytes) {}
  const SurfaceProbe& at(int i, int j) const {
    return *reinterpret_cast<const SurfaceProbe*>(tl + i * step + j * row);
  }
};

// Whether the probe's surface has a highlight at all (0 on a miss).
inline bool has_highlight(const SurfaceProbe& p) { return p.specular.r > 0.0f || p.specular.g > 0.0f || p.specular.b > 0.0f; }

// The highlight radiance (linear RGB) that the pixel whose corners are `corners`
// (physical TL, TR, BL, BR) may hold beyond the mean of what the corners saw. Zero
// unless all four corners hit a surface with a highlight. Lights whose largest possible
// highlight in the pixel stays below `visible` (per channel: increments smaller than this
// cannot show on the display) are not examined; that bound is the pixel's own, so the
// answer depends on nothing but the stencil, whatever tile or block it is asked from.
// With `stencil` (the pixel's corners and a ring around them, as
// normal_interpolation_error reads it), the hull is widened by how
// far the normals inside the pixel may lie from the bilinear interpolation of the
// corners'; it is computed only for a light that gets past the cheap bounds. Without it,
// the bilinear model alone.
// `step_limit` as for normal_interpolation_error. With `normal_spreads` (normal_map_spreads
// in render/texture_range.h), the hull is widened as well by how far the corners' normal
// map may turn the normals between them (normal_map_spread).
// With `points`, bit p is set (never cleared) for each physical lattice point p
// (aa/lattice.h) at which a light's highlight that adds to the answer may show: where the
// lobe, at the bilinear d less the normals' interpolation bound, reaches `visible` x 25 / 4
// (what a zone of 4 of the 25 points left untraced could hide of the pixel's mean); where
// it reaches that at none, the point nearest the peak.
glm::vec3 hidden_highlight(const Scene& scene, const SurfaceProbe corners[4], glm::vec3 visible,
                           const ProbeStencil* stencil = nullptr,
                           float step_limit = std::numeric_limits<float>::infinity(),
                           const std::vector<TextureSpread>* normal_spreads = nullptr, uint32_t* points = nullptr);

// The bound (|n_xx| + |n_yy|) / 8 for the pixel whose corners are the stencil's (0, 0),
// (1, 0), (0, 1), (1, 1), from second differences along rows and columns at each of them
// (the stencil's (-1, -1) to (2, 2) must exist). A difference counts only where
// its three corners hit the same material with a highlight: across a silhouette or a
// material boundary the normals are of different surfaces. 0 unless all four corners
// have a highlight. Where the second differences at the two ends of an edge of the pixel
// point in nearly opposite directions (cosine below -kStepCosine), the normal steps
// between those corners by about the mean of their lengths, and half of that step is a
// bound too, unless it exceeds `step_limit` (a distance between unit normals: the
// visibility map's angle, whose edges the map flags).
float normal_interpolation_error(const ProbeStencil& stencil,
                                 float step_limit = std::numeric_limits<float>::infinity());
inline constexpr float kStepCosine = 0.9f;

// Geometry of the test, exposed for tests: distance from the origin to the convex hull of
// four 2-D points (0 when inside), and the area of the quad p0 p1 p3 p2 (bilinear order:
// TL, TR, BR, BL).
float origin_distance_to_hull(const glm::vec2 p[4]);
float bilinear_quad_area(const glm::vec2 p[4]);
// The Phong lobe cos^s of the mirror direction's angle where |n - h| = distance, and an
// upper bound of it that costs one exp.
float lobe_at(float distance, float shininess);
float lobe_bound(float distance, float shininess);

}  // namespace zz
