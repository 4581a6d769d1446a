#include "scene/texture.h"

#include <algorithm>
#include <cmath>

namespace zz {

namespace {

// Reduces a coordinate to one period of its wrap mode before the conversion to texels, so
// a large uv (1e20) cannot overflow the conversion to long.
float reduce(float u, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::Repeat: return u - std::floor(u);
    case TextureWrap::MirroredRepeat: return u - 2.0f * std::floor(0.5f * u);  // [0, 2)
    case TextureWrap::ClampToEdge: return std::clamp(u, -1.0f, 2.0f);
  }
  return u;
}

// reduce() in four lanes, for finite coordinates.
float4 reduce4(float4 u, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::Repeat: return u - floor(u);
    case TextureWrap::MirroredRepeat: return u - float4(2.0f) * floor(float4(0.5f) * u);
    case TextureWrap::ClampToEdge: return min(max(u, float4(-1.0f)), float4(2.0f));  // std::clamp's values
  }
  return u;
}

}  // namespace

// Texel index i wrapped into [0, n) (OpenGL 4.6 §8.14.2 wrap functions).
int wrap_index(long i, int n, TextureWrap wrap) {
  // Inside the texture every mode is the identity: the bilinear footprint of a reduced
  // coordinate is there but at the border, and the 64-bit divisions below are not free.
  if (i >= 0 && i < n) return int(i);
  switch (wrap) {
    case TextureWrap::Repeat: {
      long m = i % n;
      return int(m < 0 ? m + n : m);
    }
    case TextureWrap::MirroredRepeat: {
      long period = 2L * n, m = i % period;
      if (m < 0) m += period;
      return int(m < n ? m : period - 1 - m);
    }
    case TextureWrap::ClampToEdge: return int(std::clamp<long>(i, 0, n - 1));
  }
  return 0;
}

namespace {

// The texels a bilinear lookup at reduced coordinates (u, v) blends (TL, TR, BL, BR) and
// its weights: texel centres at (i + 0.5) / width, neighbours wrapped by the wrap modes.
struct BilinearTaps {
  size_t index[4];
  float tx, ty;
};

BilinearTaps bilinear_taps(const Texture& t, float u, float v) {
  const float x = u * float(t.width) - 0.5f, y = v * float(t.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const long ix = long(fx), iy = long(fy);
  const size_t x0 = size_t(wrap_index(ix, t.width, t.wrap_s)), x1 = size_t(wrap_index(ix + 1, t.width, t.wrap_s));
  const size_t r0 = size_t(wrap_index(iy, t.height, t.wrap_t)) * size_t(t.width);
  const size_t r1 = size_t(wrap_index(iy + 1, t.height, t.wrap_t)) * size_t(t.width);
  return {{r0 + x0, r0 + x1, r1 + x0, r1 + x1}, x - fx, y - fy};
}

}  // namespace

glm::vec4 Texture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0 || texel_count() < size_t(width) * size_t(height)) return glm::vec4(1.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return texel(0);
  const float u = reduce(uv.x, wrap_s), v = reduce(uv.y, wrap_t);
  if (filter == TextureFilter::Nearest) {
    const int x = wrap_index(long(std::floor(u * float(width))), width, wrap_s);
    const int y = wrap_index(long(std::floor(v * float(height))), height, wrap_t);
    return texel(size_t(y) * size_t(width) + size_t(x));
  }
  const BilinearTaps taps = bilinear_taps(*this, u, v);
  const float tx = taps.tx, ty = taps.ty;
  const glm::vec4 a = texel(taps.index[0]), b = texel(taps.index[1]);
  const glm::vec4 c = texel(taps.index[2]), d = texel(taps.index[3]);
  return (a * (1.0f - tx) + b * tx) * (1.0f - ty) + (c * (1.0f - tx) + d * tx) * ty;
}

void Texture::sample4(float4 u, float4 v, float4 rgba[4]) const {
  const bool bilinear_rgba8 = filter == TextureFilter::Linear && texels.empty() && width > 0 && height > 0 &&
                              texels8.size() >= size_t(width) * size_t(height);
  if (!bilinear_rgba8 || !(isfinite(u) & isfinite(v)).all()) {
    alignas(16) float c[4][4];  // c[channel][lane]
    for (int lane = 0; lane < 4; ++lane) {
      const glm::vec4 t = sample(glm::vec2(u[lane], v[lane]));
      for (int ch = 0; ch < 4; ++ch) c[ch][lane] = t[ch];
    }
    for (int ch = 0; ch < 4; ++ch) rgba[ch] = float4::load(c[ch]);
    return;
  }
  // sample()'s bilinear path in lanes, the same operations: reduce, bilinear_taps' texel
  // coordinates and weights, and the weighted sum; the texels' bytes decoded lane by lane.
  const float4 x = reduce4(u, wrap_s) * float4(float(width)) - float4(0.5f);
  const float4 y = reduce4(v, wrap_t) * float4(float(height)) - float4(0.5f);
  const float4 fx = floor(x), fy = floor(y);
  const float4 tx = x - fx, ty = y - fy;
  alignas(16) int32_t ix[4], iy[4];
  int4(_mm_cvttps_epi32(fx)).store(ix);  // integral floats within +-2 periods of the texture
  int4(_mm_cvttps_epi32(fy)).store(iy);
  alignas(16) float tap[4][4][4];  // tap[corner TL, TR, BL, BR][channel][lane]
  for (int lane = 0; lane < 4; ++lane) {
    const size_t x0 = size_t(wrap_index(ix[lane], width, wrap_s)), x1 = size_t(wrap_index(ix[lane] + 1L, width, wrap_s));
    const size_t r0 = size_t(wrap_index(iy[lane], height, wrap_t)) * size_t(width);
    const size_t r1 = size_t(wrap_index(iy[lane] + 1L, height, wrap_t)) * size_t(width);
    const uint32_t p[4] = {texels8[r0 + x0], texels8[r0 + x1], texels8[r1 + x0], texels8[r1 + x1]};
    for (int k = 0; k < 4; ++k) {
      tap[k][0][lane] = colour_of_byte[p[k] & 0xffu];
      tap[k][1][lane] = colour_of_byte[(p[k] >> 8) & 0xffu];
      tap[k][2][lane] = colour_of_byte[(p[k] >> 16) & 0xffu];
      tap[k][3][lane] = alpha_of_byte[p[k] >> 24];
    }
  }
  const float4 one(1.0f);
  for (int ch = 0; ch < 4; ++ch) {
    const float4 a = float4::load(tap[0][ch]), b = float4::load(tap[1][ch]);
    const float4 c = float4::load(tap[2][ch]), d = float4::load(tap[3][ch]);
    rgba[ch] = (a * (one - tx) + b * tx) * (one - ty) + (c * (one - tx) + d * tx) * ty;
  }
}

}  // namespace zz
