// Self-intersection avoidance by offsetting the origin in integer ULPs (Waechter &
// Binder, "A Fast and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems,
// ch. 6, 2019).
#include <bit>
#include <cmath>
#include <cstdint>

#include "accel/ray.h"

namespace zz {
namespace {

// Constants of the chapter's Listing 6-1: below kOrigin (in |p|) a fixed float offset
// of kFloatScale * n is used, because integer ULP steps near 0 are too fine; kIntScale
// ULPs per unit normal otherwise.
// Measured limits of these published constants (tests/robust/scale_test.cpp): 256 ULPs
// is ~2 scene lengths for a scene placed 1e5 of its own lengths from the origin (light
// leaks at contact shadows; 32 ULPs removes them and still passes ray_offset_test, 16 does
// not), and the absolute 1/65536 near 0 is 15% of a 1e-4-sized scene at the origin. A
// tight, scale-free offset needs the hit point's error bound (pbrt-v4), i.e. the
// triangle's vertices, which this (p, n) signature does not carry.
constexpr float kOrigin = 1.0f / 32.0f;
constexpr float kFloatScale = 1.0f / 65536.0f;
constexpr float kIntScale = 256.0f;

float offset_component(float p, float n) {
  int32_t of_i = int32_t(kIntScale * n);
  // Moving the bit pattern towards larger magnitude for positive p means +of_i, and for
  // negative p the pattern grows with |p|, so the step flips sign.
  int32_t bits = std::bit_cast<int32_t>(p);
  float p_i = std::bit_cast<float>(bits + ((p < 0.0f) ? -of_i : of_i));
  return std::fabs(p) < kOrigin ? p + kFloatScale * n : p_i;
}

}  // namespace

glm::vec3 offset_ray_origin(glm::vec3 p, glm::vec3 n) {
  return {offset_component(p.x, n.x), offset_component(p.y, n.y), offset_component(p.z, n.z)};
}

}  // namespace zz
