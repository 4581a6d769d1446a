// An RGBA texture in linear float with its glTF sampler state: wrap mode per axis
// (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT) and nearest or bilinear filtering.
// No mipmaps: minification samples the base level with the same filter.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace zz {

enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class TextureFilter : uint8_t { Linear, Nearest };

struct Texture {
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> texels;  // linear RGB (sRGB decoded where the glTF says colour)
  TextureWrap wrap_s = TextureWrap::Repeat;  // along u (x)
  TextureWrap wrap_t = TextureWrap::Repeat;  // along v (y, row 0 at v = 0)
  TextureFilter filter = TextureFilter::Linear;

  glm::vec4 sample(glm::vec2 uv) const;
};

}  // namespace zz
