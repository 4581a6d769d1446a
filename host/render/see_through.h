// Rays that go on past what they first hit, lane by lane in 4-ray packets: camera rays
// past alpha cut-outs and the camera's clipping planes, shadow rays through BLEND
// surfaces and glass (render/shader.h says what the shader does with them).
#pragma once

#include <glm/glm.hpp>

#include "accel/bvh.h"
#include "render/ray_counters.h"
#include "scene/camera.h"
#include "scene/lights.h"
#include "scene/scene.h"

namespace zz {

// Beyond this many see-through layers a ray counts as blocked (shadow) or as a miss, and
// RayCounters::layer_limit counts it (the render warns). Each layer costs a traversal only
// where there are layers; stacked foliage cards and decals reach tens, not hundreds.
inline constexpr int kMaxSeeThroughLayers = 256;
// Beyond this many BLEND surfaces along a camera, mirror or refraction ray (each a level of
// the shader's recursion, about 2 kB of stack), the next one is weighed by its alpha over
// nothing: what lies behind it is left out (and counted in layer_limit too).
inline constexpr int kMaxBlendLayers = 64;

// Where a lane's ray hit; lanes are rewritten when a ray continues past a cut-out.
struct LaneHits {
  float t[4], u[4], v[4];
  int prim[4];
  explicit LaneHits(const HitPacket4& h) {
    for (int i = 0; i < 4; ++i) t[i] = h.t[i], u[i] = h.u[i], v[i] = h.v[i], prim[i] = h.prim[i];
  }
  void take(const HitPacket4& h, int i) { t[i] = h.t[i], u[i] = h.u[i], v[i] = h.v[i], prim[i] = h.prim[i]; }
};

// Fills a packet lane by lane, then loads it once. Unused lanes stay harmless
// (zero origin, +z direction, tmax 0) and are masked off anyway.
struct PacketBuilder {
  alignas(16) float o[3][4] = {};
  alignas(16) float d[3][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {1, 1, 1, 1}};
  alignas(16) float tmax[4] = {};

  void set(int i, glm::vec3 origin, glm::vec3 dir, float t) {
    for (int c = 0; c < 3; ++c) {
      o[c][i] = origin[c];
      d[c][i] = dir[c];
    }
    tmax[i] = t;
  }
  RayPacket4 packet() const {
    return {float4::load(o[0]), float4::load(o[1]), float4::load(o[2]), float4::load(d[0]),
            float4::load(d[1]), float4::load(d[2]), float4::load(tmax)};
  }
};

// Moves the active lanes that hit a cut-out texel (MASK below the cutoff, BLEND alpha 0)
// on to the first surface behind it, one packet per layer; `skipped` gets the distance
// travelled through them. Bounded: beyond kMaxSeeThroughLayers a ray escapes (a miss).
void pass_cutouts(const Scene& scene, const Bvh& bvh, const RayPacket4& rays, int active_bits, LaneHits& hits,
                  float skipped[4], RayCounters& counters);

// Camera clipping (scene/camera.h CameraClip). A lane whose first hit lies nearer than the
// near plane is traced again from where it crosses the plane (`skipped` gets the distance
// to it); a lane moving along or away from the plane from before it sees nothing.
void clip_near(const Scene& scene, const Bvh& bvh, const RayPacket4& rays, int active_bits, LaneHits& hits,
               float skipped[4], const CameraClip& clip, RayCounters& counters);

// A lane whose hit lies beyond the far plane sees the background.
void clip_far(const Scene& scene, int active_bits, LaneHits& hits, const CameraClip& clip);

// The light arriving along each lane of a shadow packet through see-through surfaces:
// alpha cut-outs and BLEND surfaces pass (1 - alpha) of it, transmissive non-metal
// surfaces transmission x base colour at each crossing, and the path inside a volume
// exp(-sigma_a d) (Beer's law). The shadow ray is not bent. A lane that hits anything
// opaque, or more than kMaxSeeThroughLayers surfaces, gets zero. `rays` is moved on
// layer by layer. Compiled for each kernel's textures, alpha and glass (shader.h).
template <bool kTextured, bool kSeeThrough, bool kGlass>
void shadow_transmittance(const Scene& scene, const Bvh& bvh, const Light& light, PacketBuilder& rays, int lanes,
                          glm::vec3 through[4], RayCounters& counters);

}  // namespace zz
