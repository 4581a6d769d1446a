#include "core/tonemap.h"

#include <array>
#include <cmath>

namespace zz {

float4 exp_neg4(float4 x) {
  // exp(x) = 2^n * exp(r), n = round(x / ln2), r = x - n ln2 in [-ln2/2, ln2/2].
  x = max(x, float4(-87.0f));  // below this exp underflows to 0 anyway
  x = min(x, float4(0.0f));
  const float4 log2e(1.44269504088896341f);
  float4 n = floor(x * log2e + float4(0.5f));
  // Cody-Waite split of ln2 for an exact reduction.
  float4 r = x - n * float4(0.693359375f);
  r = r + n * float4(2.12194440e-4f);
  float4 p(1.9875691500e-4f);
  p = p * r + float4(1.3981999507e-3f);
  p = p * r + float4(8.3334519073e-3f);
  p = p * r + float4(4.1665795894e-2f);
  p = p * r + float4(1.6666665459e-1f);
  p = p * r + float4(5.0000001201e-1f);
  p = p * (r * r) + r + float4(1.0f);
  __m128i e = _mm_add_epi32(_mm_cvtps_epi32(n), _mm_set1_epi32(127));
  e = _mm_slli_epi32(e, 23);
  return p * float4(_mm_castsi128_ps(e));
}

namespace {

constexpr int kSrgbSegments = 4096;

struct SrgbTable {
  alignas(16) std::array<float, kSrgbSegments + 2> value;
  SrgbTable() {
    for (int i = 0; i <= kSrgbSegments + 1; ++i) {
      double l = std::min(1.0, double(i) / kSrgbSegments);
      value[i] = float(l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055);
    }
  }
};

const SrgbTable& srgb_table() {
  static const SrgbTable table;
  return table;
}

}  // namespace

float4 srgb_encode4(float4 linear01) {
  const SrgbTable& t = srgb_table();
  float4 x = clamp(linear01, float4(0.0f), float4(1.0f)) * float4(float(kSrgbSegments));
  float4 i = floor(x);
  float4 f = x - i;
  alignas(16) int32_t idx[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(idx), _mm_cvttps_epi32(i));
  float4 a(t.value[idx[0]], t.value[idx[1]], t.value[idx[2]], t.value[idx[3]]);
  float4 b(t.value[idx[0] + 1], t.value[idx[1] + 1], t.value[idx[2] + 1], t.value[idx[3] + 1]);
  return a + (b - a) * f;
}

float4 ToneMap::apply4(float4 c) const {
  // NaN and negatives -> 0; +Inf -> exp(-inf) = 0 -> display 1.
  mask4 valid = c > float4(0.0f);
  float4 scaled = select(valid, c * float4(exposure), float4(0.0f));
  float4 y = float4(1.0f) - exp_neg4(-scaled);
  return srgb_encode4(y);
}

float4 ToneMap::slope4(float4 c) const {
  // u = 1 - exp(-e c), du/dc = e (1 - u); sRGB: 12.92 below 0.0031308, else
  // d/du (1.055 u^(1/2.4) - 0.055) = (T + 0.055) / (2.4 u).
  const float4 e(exposure);
  const float4 scaled = select(c > float4(0.0f), c * e, float4(0.0f));
  const float4 rest = exp_neg4(-scaled);  // 1 - u
  const float4 u = float4(1.0f) - rest;
  const float4 power = (srgb_encode4(u) + float4(0.055f)) / (float4(2.4f) * max(u, float4(0.0031308f)));
  return e * rest * select(u <= float4(0.0031308f), float4(12.92f), power);
}

}  // namespace zz
