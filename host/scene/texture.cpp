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
  alignas(16) float c[4][4];  // c[channel][lane]
  alignas(16) float us[4], vs[4];
  u.store(us);
  v.store(vs);
  const bool bilinear_rgba8 = filter == TextureFilter::Linear && texels.empty() && width > 0 && height > 0 &&
                              texels8.size() >= size_t(width) * size_t(height);
  for (int lane = 0; lane < 4; ++lane) {
    if (!bilinear_rgba8 || !std::isfinite(us[lane]) || !std::isfinite(vs[lane])) {
      const glm::vec4 t = sample(glm::vec2(us[lane], vs[lane]));
      for (int ch = 0; ch < 4; ++ch) c[ch][lane] = t[ch];
      continue;
    }
    // sample()'s bilinear path, with the four texels' bytes decoded into their weighted sum.
    const BilinearTaps taps = bilinear_taps(*this, reduce(us[lane], wrap_s), reduce(vs[lane], wrap_t));
    const float tx = taps.tx, ty = taps.ty;
    const uint32_t p[4] = {texels8[taps.index[0]], texels8[taps.index[1]], texels8[taps.index[2]],
                           texels8[taps.index[3]]};
    for (int ch = 0; ch < 4; ++ch) {
      const std::array<float, 256>& table = ch == 3 ? alpha_of_byte : colour_of_byte;
      const unsigned shift = 8u * unsigned(ch);
      const float a = table[(p[0] >> shift) & 0xffu], b = table[(p[1] >> shift) & 0xffu];
      const float cc = table[(p[2] >> shift) & 0xffu], d = table[(p[3] >> shift) & 0xffu];
      c[ch][lane] = (a * (1.0f - tx) + b * tx) * (1.0f - ty) + (cc * (1.0f - tx) + d * tx) * ty;
    }
  }
  for (int ch = 0; ch < 4; ++ch) rgba[ch] = float4::load(c[ch]);
}

}  // namespace zz
