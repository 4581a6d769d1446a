// What the texture footprint correction (texture_detail.h) needs of a camera ray's first
// hit beyond its SurfaceProbe: the direct light per unit albedo that reached it, and where
// on which triangle it is, to recompute the normal map's frame and the lights there. Kept
// small: the corner field holds one per corner of its bands (aa/corner_field.h).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace zz {

// Lights lit one by one at the footprint's samples; a scene with more has only the albedo
// part of the correction.
inline constexpr int kFootprintLights = 8;

struct FootprintProbe {
  // Direct light per unit albedo, sum over lights of E_l V_l cos_l / pi (V_l what reached
  // the hit of light l): the diffuse term is albedo * irradiance.
  glm::vec3 irradiance{0.0f};
  int32_t prim = -1;       // the triangle hit; -1 on a miss
  float u = 0.0f, v = 0.0f;  // its barycentrics there
  float side = 1.0f;       // +1 where the ray hit the triangle's front, -1 its back
  // What the hit's radiance is multiplied by on its way to the camera: 1 for the primary
  // hit; the reflection and refraction weights along the path, and Beer's absorption, for
  // what a mirror or a glass shows.
  glm::vec3 weight{1.0f};
};

}  // namespace zz
