#include "scene/lights.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace zz {

std::optional<glm::vec3> unit_direction(glm::vec3 v) {
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return std::nullopt;
  const float largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(largest > 0.0f)) return std::nullopt;
  // Where |v|^2 neither overflows nor loses precision to denormals, glm's own normalize:
  // the directions scenes have always had keep their bits (and their images).
  const float length2 = glm::dot(v, v);
  if (length2 >= std::numeric_limits<float>::min() && std::isfinite(length2)) return glm::normalize(v);
  const glm::vec3 scaled = v / largest;  // largest component +-1: its square neither overflows nor underflows
  return scaled / std::sqrt(glm::dot(scaled, scaled));
}

std::string light_problem(const Light& light) {
  if (light.intensity.x < 0.0f || light.intensity.y < 0.0f || light.intensity.z < 0.0f)
    return "negative colour or intensity (KHR_lights_punctual: colour in [0, 1], intensity >= 0)";
  // A rig's numbers stop at 1e30 too: beyond, a light's sums overflow float near it.
  if (std::max({light.intensity.x, light.intensity.y, light.intensity.z}) > 1e30f)
    return "colour times intensity above 1e30";
  if (light.range < 0.0f) return "negative range (> 0, or 0 for none)";
  if (light.type == Light::Type::Spot && !(light.outer_cone > 0.0f))
    return "spot cone closed (KHR_lights_punctual: outer cone angle > 0)";
  return {};
}

bool can_light(const Light& light) {
  const bool some = light.intensity.x > 0.0f || light.intensity.y > 0.0f || light.intensity.z > 0.0f;
  return some && (light.type != Light::Type::Spot || light.outer_cone > 0.0f);
}

}  // namespace zz
