// Rays and hits, single and in SSE packets of 4 (SoA, one lane per ray).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>

#include "core/simd.h"

namespace zz {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Ray {
  glm::vec3 origin;
  glm::vec3 dir;            // need not be normalised; t is in units of |dir|
  float tmax = kInfinity;   // tmin is 0: secondary origins are offset (offset_ray_origin)
};

struct Hit {
  float t = kInfinity;
  float u = 0.0f, v = 0.0f;  // barycentrics of vertices 1 and 2
  int32_t prim = -1;         // triangle index, -1 = miss
  bool hit() const { return prim >= 0; }
};

struct alignas(16) RayPacket4 {
  float4 ox, oy, oz;
  float4 dx, dy, dz;
  float4 tmax;
};

struct alignas(16) HitPacket4 {
  float4 t;
  float4 u, v;
  int4 prim;  // -1 = miss
};

// A point just off a surface, so that a ray spawned from it in direction d never hits
// the surface it left (Waechter & Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6). n is the geometric normal on the side the
// ray leaves from. No scene-size epsilon: the offset scales with |p|.
glm::vec3 offset_ray_origin(glm::vec3 p, glm::vec3 n);

}  // namespace zz
