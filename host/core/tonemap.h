// The one global tone-mapping operator (HDR linear radiance -> display [0,1]):
//   T(c) = srgb_encode(1 - exp(-exposure * c))      per channel
// An exponential curve: monotone, maps [0, inf) onto [0, 1), never clips a highlight
// abruptly, and needs no scene-dependent white point. NaN and negative inputs map to 0,
// +Inf maps to 1. The adaptive sampler compares colours with the SSE version of exactly
// this operator (ALGORITHM.md §2), so display image and comparisons never disagree.
#pragma once

#include "core/color.h"
#include "core/simd.h"

namespace zz {

// exp(x) for x <= 0 in SSE (Cephes-style range reduction + degree-5 polynomial,
// relative error < 2e-7). Deterministic: pure IEEE arithmetic, no libm.
float4 exp_neg4(float4 x);

// sRGB transfer function (IEC 61966-2-1) on [0,1], SSE, from a 4096-segment table with
// linear interpolation (max abs error < 2e-5).
float4 srgb_encode4(float4 linear01);

struct ToneMap {
  float exposure = 1.0f;

  float4 apply4(float4 c) const;
  Rgb4 apply4(const Rgb4& c) const { return {apply4(c.r), apply4(c.g), apply4(c.b)}; }
  float apply(float c) const { return apply4(float4(c))[0]; }
  // dT/dc, the display change per unit of radiance at c >= 0. T is concave, so
  // T(c + x) - T(c) <= slope(c) x: an increment below eps / slope(c) cannot show.
  float4 slope4(float4 c) const;
};

}  // namespace zz
