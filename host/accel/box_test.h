// Conservative ray/box slab test shared by the single-ray and packet traversals.
#pragma once

#include <cmath>

#include "core/simd.h"

namespace zz {

// Robust far-distance scale (Ize, "Robust BVH Ray Traversal", JCGT 2013; pbrt-v4's
// 1 + 2 gamma(3)), widened to 2^-18 so that a box is never culled while a triangle in it
// can still produce a hit whose rounded t is at most the current tmax: the BVH then
// returns exactly what brute force over all triangles returns.
inline constexpr float kBoxFarScale = 1.0f + 1.0f / 262144.0f;

// 1/d with zero (and tiny) components replaced by +-1e-30: (b - o) * rcp is then never
// 0 * inf = NaN, and the slab for a direction parallel to it stays [-huge, +huge].
inline float safe_rcp(float d) {
  float a = std::fabs(d) < 1e-30f ? std::copysign(1e-30f, d) : d;
  return 1.0f / a;
}

}  // namespace zz
