// Rays and hits, single and in SSE packets of 4 (SoA, one lane per ray).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>

#include "core/simd.h"

namespace zz {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// gamma(n) = n eps / (1 - n eps), eps = 2^-24: the bound on the relative error of n
// rounded float operations (pbrt-v4, 6.8.1).
constexpr float gamma(int n) {
  constexpr float eps = std::numeric_limits<float>::epsilon() * 0.5f;
  return (float(n) * eps) / (1.0f - float(n) * eps);
}

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
  glm::vec3 origin(int lane) const { return {ox[lane], oy[lane], oz[lane]}; }
  glm::vec3 direction(int lane) const { return {dx[lane], dy[lane], dz[lane]}; }
};

struct alignas(16) HitPacket4 {
  float4 t;
  float4 u, v;
  int4 prim;  // -1 = miss
};

// A hit point on a triangle, interpolated from its vertices with barycentrics
// (w, u, v), w = 1 - u - v, and a conservative bound of the rounding error of that
// interpolation per axis: gamma(7) * (|w p0| + |u p1| + |v p2|) (pbrt-v4, 6.8.5).
struct SurfacePosition {
  glm::vec3 p;
  glm::vec3 error;
};
SurfacePosition interpolate_hit(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, float u, float v);

// A point just off a surface, so that a ray spawned from it on the side n points to never
// hits the surface it left (pbrt-v4, "Robust Spawned Ray Origins", 6.8.6): move past the
// error box along the normal (by its largest axis bound, see ray_offset.cpp), then round
// away from the surface.
// No scene-size epsilon: the offset is a few ULPs of the vertex coordinates.
glm::vec3 offset_ray_origin(const SurfacePosition& hit, glm::vec3 n);

}  // namespace zz
