// Punctual lights (KHR_lights_punctual semantics): point and spot intensity in
// candela (W/sr in our radiometric units), directional in lux (W/m^2).
#pragma once

#include <glm/glm.hpp>

#include <optional>
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

// v / |v| for any finite v but zero. v is scaled by its largest component first: glm's
// normalize squares v, so a length past ~1e19 overflowed to a zero vector and one below
// ~1e-19 underflowed (a light node scaled by 1e20 or 1e-23 lost its direction).
std::optional<glm::vec3> unit_direction(glm::vec3 v);

// Why `light` is not one KHR_lights_punctual allows (a negative colour, intensity or range,
// a closed spot cone), or empty. The loaders refuse such a light: it would light nothing,
// or darken. A spot's inner cone at or past its outer one is left alone: exporters write
// it (Blender's, for a spot with no blend) and it means a hard-edged cone.
std::string light_problem(const Light& light);

// Whether the light can reach anything: some intensity, and a spot's cone open.
bool can_light(const Light& light);

}  // namespace zz
