// Punctual lights (KHR_lights_punctual semantics): point and spot intensity in
// candela (W/sr in our radiometric units), directional in lux (W/m^2).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
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

// The unit normal of triangle (p0, p1, p2) by its winding: glm::normalize's bits where
// |cross|^2 is a normal float, else unit_direction's (edges past ~1e9 overflowed |cross|^2
// to a zero normal, and under the workers' flush-to-zero, edges below ~1e-10 gave NaN).
inline glm::vec3 triangle_normal(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
  const glm::vec3 c = glm::cross(p1 - p0, p2 - p0);
  const float length2 = glm::dot(c, c);
  if (length2 >= 1.17549435e-38f && length2 <= 3.40282347e38f) return glm::normalize(c);
  return unit_direction(c).value_or(glm::vec3(0.0f, 0.0f, 1.0f));
}

// A point or spot light's shadow segment ends this fraction of its length short of the
// light, so a surface the light lies on (a lamp set on the ceiling) does not shadow
// it: t = 1 is the light, and a hit there is rounding (pbrt's ShadowEpsilon).
inline constexpr float kShadowEpsilon = 1e-4f;

// Why `light` is not one KHR_lights_punctual allows (a negative colour, intensity or range,
// a closed spot cone, a cone angle outside [0, pi/2]), or empty. The loaders refuse such a
// light: it would light nothing, or darken, or light behind itself. A spot's inner cone at
// or past its outer one is only warned about (spot_cone_warning): exporters write it
// (Blender's, for a spot with no blend) and it means a hard-edged cone.
std::string light_problem(const Light& light);

// What the loaders warn of a spot whose inner cone is not inside its outer one, else empty.
std::string spot_cone_warning(const Light& light);

// Whether the light can reach anything: some intensity, and a spot's cone open.
bool can_light(const Light& light);

// The spot cone's factor is clamp((cos - cos_outer) * scale, 0, 1)^2 (the glTF spec's sample
// code); scale = 1 / (cos_inner - cos_outer), floored as the spec's 1 / max(0.001, ...) for
// a hard-edged cone, but at most half of (1 - cos_outer): a narrow cone must still reach 1
// on its axis, where the fixed floor left a 1-degree hard spot at 1/43 of its intensity.
// Cones whose outer angle is over 3.6 degrees (1 - cos_outer >= 0.002) keep the spec's floor
// and their edge; cones under 0.03 degrees, whose cosine rounds to 1, stay dark, as before.
inline float spot_scale(float cos_inner, float cos_outer) {
  const float floor = std::max(std::min(0.001f, 0.5f * (1.0f - cos_outer)), 1e-7f);  // 1e-7: cos_outer rounded to 1
  return 1.0f / std::max(floor, cos_inner - cos_outer);
}

}  // namespace zz
