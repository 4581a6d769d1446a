#include "render/lighting.h"

#include <algorithm>
#include <cmath>

#include "accel/ray.h"

namespace zz {

bool light_towards(const Light& light, glm::vec3 p, glm::vec3& to_light, float& tmax, glm::vec3& radiance_scale) {
  if (light.type == Light::Type::Directional) {
    to_light = -glm::normalize(light.direction);
    tmax = kInfinity;
    radiance_scale = light.intensity;
    return true;
  }
  glm::vec3 d = light.position - p;
  float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return false;
  float dist = std::sqrt(dist2);
  to_light = d / dist;
  tmax = dist;
  float falloff = 1.0f / dist2;
  if (light.range > 0.0f) {  // KHR_lights_punctual's recommended window: clamp(1 - (d/r)^4, 0, 1) / d^2
    float r = dist / light.range;
    falloff *= std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
  }
  if (light.type == Light::Type::Spot) {
    float cd = glm::dot(glm::normalize(light.direction), -to_light);
    float cos_outer = std::cos(light.outer_cone), cos_inner = std::cos(light.inner_cone);
    float scale = spot_scale(cos_inner, cos_outer);
    float t = std::clamp((cd - cos_outer) * scale, 0.0f, 1.0f);
    falloff *= t * t;
  }
  radiance_scale = light.intensity * falloff;
  return falloff > 0.0f;
}

}  // namespace zz
