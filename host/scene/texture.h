// An RGBA texture in linear float with its glTF sampler state: wrap mode per axis
// (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT) and nearest or bilinear filtering.
// No mipmaps: minification samples the base level with the same filter.
//
// Storage: 8-bit images keep their bytes (RGBA8, a quarter of float RGBA) with one table per
// texture that maps a byte to the linear float the decoder would have stored (sRGB decode
// included), so a lookup returns the very same floats and sampling stays bit-identical; the
// bilinear fetch then touches 16 bytes instead of 64 (texel loads were 41 % of sample() on
// ToyCar, mostly cache misses). 16-bit images and hand-made textures use float RGBA.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "core/simd.h"

namespace zz {

enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter : uint8_t { Linear, Nearest };

struct Texture {
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> texels;  // float storage: linear RGB (sRGB decoded where the glTF says colour)
  std::vector<uint32_t> texels8;  // RGBA8 storage (R in the low byte), used when texels is empty
  std::array<float, 256> colour_of_byte{};  // RGBA8: byte -> linear R, G or B
  std::array<float, 256> alpha_of_byte{};   // RGBA8: byte -> alpha
  TextureWrap wrap_s = TextureWrap::Repeat;  // along u (x)
  TextureWrap wrap_t = TextureWrap::Repeat;  // along v (y, row 0 at v = 0)
  TextureFilter filter = TextureFilter::Linear;

  size_t texel_count() const { return texels.empty() ? texels8.size() : texels.size(); }
  glm::vec4 texel(size_t i) const {
    if (!texels.empty()) return texels[i];
    const uint32_t p = texels8[i];
    return {colour_of_byte[p & 0xffu], colour_of_byte[(p >> 8) & 0xffu], colour_of_byte[(p >> 16) & 0xffu],
            alpha_of_byte[p >> 24]};
  }
  glm::vec4 sample(glm::vec2 uv) const;
  // Four lanes of sample() at (u[i], v[i]), returned as R, G, B, A rows; the same floats as
  // sample() gives lane by lane.
  void sample4(float4 u, float4 v, float4 rgba[4]) const;
};

// Texel index i wrapped into [0, n) by the wrap mode (OpenGL 4.6 §8.14.2).
int wrap_index(long i, int n, TextureWrap wrap);

}  // namespace zz
