// Direct lighting of 4 hit points at once (SoA, one lane per ray of a packet): the light's
// direction, distance and irradiance factor (glTF KHR_lights_punctual) for each lane.
// Every lane runs the same IEEE operations in the same order as the scalar light_towards
// (render/lighting.h; no reassociation, no reciprocal approximations, the build uses
// -ffp-contract=off), so each lane's result is bit-identical.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

#include "accel/ray.h"
#include "core/simd.h"
#include "scene/lights.h"

namespace zz {

inline vec3x4 broadcast(glm::vec3 v) { return {float4(v.x), float4(v.y), float4(v.z)}; }

// The lanes' copies of a light's incident direction and irradiance factor.
struct LightSample4 {
  vec3x4 to_light;  // unit direction from the point to the light
  vec3x4 scale;     // light.intensity * falloff (distance, range window, spot cone)
  mask4 lit;        // falloff > 0 (and the point is not at the light's position)
  mask4 towards;    // to_light holds (light_towards sets it): directional, or not at the position
};

// Per-light constants, computed once per light rather than once per lane.
struct LightConstants {
  vec3x4 position, intensity;
  vec3x4 directional_to_light;  // -normalize(direction), for directional lights
  glm::vec3 spot_axis{0.0f};    // normalize(direction)
  float cos_outer = 0.0f, spot_scale = 0.0f;
  explicit LightConstants(const Light& light)
      : position(broadcast(light.position)), intensity(broadcast(light.intensity)) {
    directional_to_light = broadcast(light.type == Light::Type::Directional ? -glm::normalize(light.direction)
                                                                            : glm::vec3(0.0f));
    if (light.type == Light::Type::Spot) {
      spot_axis = glm::normalize(light.direction);
      cos_outer = std::cos(light.outer_cone);
      const float cos_inner = std::cos(light.inner_cone);
      spot_scale = zz::spot_scale(cos_inner, cos_outer);
    }
  }
};

// std::clamp(x, 0, 1) for the lanes where it matters (NaN lanes give 0, which the callers
// treat like the scalar code's NaN: no light).
inline float4 clamp01(float4 x) { return min(max(x, float4(0.0f)), float4(1.0f)); }

inline LightSample4 light_towards4(const Light& light, const LightConstants& k, const vec3x4& p) {
  LightSample4 s;
  if (light.type == Light::Type::Directional) {
    s.to_light = k.directional_to_light;
    s.scale = k.intensity;
    s.lit = s.towards = mask4(true);
    return s;
  }
  const vec3x4 d = k.position - p;
  const float4 dist2 = dot(d, d);
  const float4 dist = sqrt(dist2);
  s.to_light = {d.x / dist, d.y / dist, d.z / dist};
  float4 falloff = float4(1.0f) / dist2;
  if (light.range > 0.0f) {  // KHR_lights_punctual's recommended window: clamp(1 - (d/r)^4, 0, 1) / d^2
    const float4 r = dist / float4(light.range);
    falloff = falloff * clamp01(float4(1.0f) - r * r * r * r);
  }
  if (light.type == Light::Type::Spot) {
    const float4 cd = float4(k.spot_axis.x) * -s.to_light.x + float4(k.spot_axis.y) * -s.to_light.y +
                      float4(k.spot_axis.z) * -s.to_light.z;
    const float4 t = clamp01((cd - float4(k.cos_outer)) * float4(k.spot_scale));
    falloff = falloff * (t * t);
  }
  s.scale = k.intensity * falloff;
  s.towards = dist2 > float4(0.0f);
  s.lit = s.towards & (falloff > float4(0.0f));
  return s;
}

}  // namespace zz
