// An RGBA texture in linear float, sampled bilinearly with wrap (glTF REPEAT default).
#pragma once

#include <glm/glm.hpp>

#include <vector>

namespace zz {

struct Texture {
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> texels;  // linear RGB (sRGB decoded where the glTF says colour)

  glm::vec4 sample(glm::vec2 uv) const;
};

}  // namespace zz
