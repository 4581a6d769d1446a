#include "scene/lights.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
  constexpr float kRightAngle = 1.5707964f;  // pi/2 rounded up: 90 degrees converted must pass
  if (light.type == Light::Type::Spot &&
      !(light.inner_cone >= 0.0f && light.inner_cone <= kRightAngle && light.outer_cone <= kRightAngle))
    return "spot cone angle outside [0, pi/2] (KHR_lights_punctual; 0 to 90 degrees in a rig)";
  return {};
}

std::string spot_cone_warning(const Light& light) {
  if (light.type != Light::Type::Spot || !(light.inner_cone >= light.outer_cone && light.outer_cone > 0.0f)) return {};
  char angles[96];
  std::snprintf(angles, sizeof angles, "an inner cone angle of %.6g rad, not below its outer %.6g rad",
                double(light.inner_cone), double(light.outer_cone));
  return "spot light '" + light.name + "' has " + angles +
         " (KHR_lights_punctual requires inner < outer): its cone has a hard edge at the outer angle";
}

bool can_light(const Light& light) {
  const bool some = light.intensity.x > 0.0f || light.intensity.y > 0.0f || light.intensity.z > 0.0f;
  return some && (light.type != Light::Type::Spot || light.outer_cone > 0.0f);
}

}  // namespace zz
