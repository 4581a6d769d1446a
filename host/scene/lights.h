// Punctual lights (KHR_lights_punctual semantics): point and spot intensity in
// candela (W/sr in our radiometric units), directional in lux (W/m^2).
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace zz {

struct Light {
  enum class Type { Point, Spot, Directional };
  Type type = Type::Point;
  std::string name;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // where the light points (spot, directional)
  glm::vec3 intensity{1.0f};                // colour * intensity
  float range = 0.0f;                       // 0 = infinite (glTF)
  float inner_cone = 0.0f;                  // spot, radians
  float outer_cone = 0.7853982f;            // spot, radians (glTF default pi/4)
};

}  // namespace zz
