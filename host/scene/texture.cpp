#include "scene/texture.h"

#include <cmath>

namespace zz {

glm::vec4 Texture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0 || texels.size() < size_t(width) * size_t(height)) return glm::vec4(1.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return texels[0];
  // Texel centres at (i + 0.5) / width; REPEAT wrapping. Reduce to [0, 1] first: a large
  // uv (1e20) would overflow the conversion to long and lose the fraction in x.
  const float u = uv.x - std::floor(uv.x), v = uv.y - std::floor(uv.y);
  float x = u * float(width) - 0.5f;
  float y = v * float(height) - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  float tx = x - fx, ty = y - fy;
  auto wrap = [](long i, int n) { long m = i % n; return int(m < 0 ? m + n : m); };
  long ix = long(fx), iy = long(fy);
  int x0 = wrap(ix, width), x1 = wrap(ix + 1, width);
  int y0 = wrap(iy, height), y1 = wrap(iy + 1, height);
  const glm::vec4& a = texels[size_t(y0) * width + x0];
  const glm::vec4& b = texels[size_t(y0) * width + x1];
  const glm::vec4& c = texels[size_t(y1) * width + x0];
  const glm::vec4& d = texels[size_t(y1) * width + x1];
  return (a * (1.0f - tx) + b * tx) * (1.0f - ty) + (c * (1.0f - tx) + d * tx) * ty;
}

}  // namespace zz
