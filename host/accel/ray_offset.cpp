// Robust spawned-ray origins from the hit point's floating-point error bound
// (Pharr, Jakob & Humphreys, Physically Based Rendering 4th ed., 6.8.5-6.8.6).
// An integer-ULP offset of the point alone (Waechter & Binder 2019) cannot know how far
// the point is from its triangle's vertices: measured here, its 256 ULPs were two scene
// lengths for a scene 1e5 of its lengths from the origin, and its fixed 1/65536 near 0 was
// 15% of a 1e-4-sized scene. The error bound scales with the vertices themselves.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "accel/ray.h"

namespace zz {

namespace {

// std::nextafter(x, +inf) and std::nextafter(x, -inf) on the bits, without the libm call
// (glibc's nextafterf works on the bits too, so these return the same values: NaN and the
// infinity in the stepping direction stay, +-0 steps to +-denorm_min, -denorm_min up to
// -0, FLT_MAX up to inf). 1.6 % of glass.json's profile was the call to nextafterf.
float next_up(float x) {
  const uint32_t b = std::bit_cast<uint32_t>(x);
  if ((b & 0x7fffffffu) > 0x7f800000u || b == 0x7f800000u) return x;  // NaN, +inf
  if ((b & 0x7fffffffu) == 0) return std::bit_cast<float>(uint32_t(1));  // +-0 -> +denorm_min
  return std::bit_cast<float>(b & 0x80000000u ? b - 1 : b + 1);
}

float next_down(float x) {
  const uint32_t b = std::bit_cast<uint32_t>(x);
  if ((b & 0x7fffffffu) > 0x7f800000u || b == 0xff800000u) return x;  // NaN, -inf
  if ((b & 0x7fffffffu) == 0) return std::bit_cast<float>(0x80000001u);  // +-0 -> -denorm_min
  return std::bit_cast<float>(b & 0x80000000u ? b + 1 : b - 1);
}

}  // namespace

SurfacePosition interpolate_hit(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, float u, float v) {
  const float w = 1.0f - u - v;
  SurfacePosition s;
  s.p = w * p0 + u * p1 + v * p2;
  // pbrt bounds the interpolation with gamma(7); one more for computing w from u and v.
  s.error = gamma(8) * (glm::abs(w * p0) + glm::abs(u * p1) + glm::abs(v * p2));
  return s;
}

glm::vec3 offset_ray_origin(const SurfacePosition& hit, glm::vec3 n) {
  // pbrt moves by dot(|n|, error). We use the largest axis bound on every axis: the
  // watertight test shears all three coordinates of the vertices relative to the origin,
  // so its rounding follows their largest magnitude. On a plane z = 0 the z bound alone
  // is 0 and the origin would stay on the plane (or 1 denormal ULP off it, which the
  // shear's products flush to 0): measured as acne on every lit floor.
  const float largest = std::max(hit.error.x, std::max(hit.error.y, hit.error.z));
  const float d = largest * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  const glm::vec3 offset = d * n;
  glm::vec3 po = hit.p + offset;
  // Round away from the surface: the addition above may have rounded back towards it.
  // Stepping by the normal's sign (not the offset's, as pbrt does) also moves a point
  // whose error bound is exactly 0 (an axis-aligned plane at 0) off the plane. The BVH
  // itself refuses t = 0 (watertight.h keeps t above its rounding bound, or settles it in double);
  // leaving the plane means the spawned ray does not depend on its own surface's t
  // rounding to exactly 0.
  for (int i = 0; i < 3; ++i) {
    if (n[i] > 0.0f)
      po[i] = next_up(po[i]);
    else if (n[i] < 0.0f)
      po[i] = next_down(po[i]);
  }
  return po;
}

}  // namespace zz
