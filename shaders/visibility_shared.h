// Layouts shared by the C++ visibility pass (host/gpu/visibility.cpp) and its GLSL
// shaders, so both sides agree on push constants and packing by construction.
#ifndef ZZ_VISIBILITY_SHARED_H
#define ZZ_VISIBILITY_SHARED_H

#ifdef __cplusplus
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
namespace zz::gpu {
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
#endif

// Flag compute invocations per group; each invocation flags ZZ_PIXELS_PER_WORD horizontal
// pixels and writes them as one uint (byte k = pixel 4*word + k), so no 8-bit storage is needed.
#define ZZ_FLAG_GROUP_X 8
#define ZZ_FLAG_GROUP_Y 8
#define ZZ_PIXELS_PER_WORD 4
#define ZZ_MAX_SUPERSAMPLE 16
#define ZZ_PLANE_GROUP 64

// A pixel's flag byte: ZZ_GEO_EDGE when flagged, with ZZ_GEO_ALONG_X when more of its
// differing sample pairs are vertical neighbours than horizontal ones (the edge runs
// along x): level 1 orients a pixel whose corners leave the orientation open by it. Bits
// ZZ_GEO_ZONE_SHIFT.. +4: the zones (ALGORITHM.md §3) its differing pairs meet, in the frame
// that bit names (vertical when along x, else horizontal): a pair across the zones at its
// midpoint's zone, a pair along them at its samples' zone.
#define ZZ_GEO_EDGE 1
#define ZZ_GEO_ALONG_X 2
#define ZZ_GEO_ZONE_SHIFT 2

// One descriptor set for both compute passes.
#define ZZ_BIND_IDS 0        // r32ui storage image: the id attachment
#define ZZ_BIND_FIRST_VERTICES 1  // vec4 per triangle: its first vertex
#define ZZ_BIND_NORMALS 2    // vec4 per triangle: unit geometric normal, material tag (float) in w
#define ZZ_BIND_PLANES 3     // vec4 per triangle per frame: normal, n.(v0 - origin)
#define ZZ_BIND_FLAGS 4      // packed flag words

// Vertex stage: clip = clip_from_view * (position - origin, 1). Camera-relative
// positions keep float precision when the scene sits far from the world origin.
// With ZZ_CLIP_PLANES (ids.vert) the camera's clipping planes too: depth along
// clip_forward.xyz, kept where clip_planes.x <= depth <= clip_planes.y.
struct RasterPush {
  mat4 clip_from_view;
  vec4 origin;
  vec4 clip_forward;
  vec4 clip_planes;
};

// Compute stage. Supersample (gx, gy) of the frame (gx in [-1, W*S]) has the ray
// direction dir00 + gx*du + gy*dv (unnormalised) from origin, i.e. CameraRays at image
// point ((gx + 0.5)/S, (gy + 0.5)/S); for an orthographic camera (limits.w = 1) the
// direction dir00 from origin + gx*du + gy*dv. The id image of a tile holds supersamples
// gx in [tile.x*S - 1, (tile.x + tile.z)*S], gy likewise: the tile plus a one-sample ring.
// The flag buffer holds the rows of the flagged pixels only (a region's, not the frame's):
// pixel (x, y) is byte (x - out_x0) % 4 of uint (y - out_y0) * frame.w + (x - out_x0) / 4.
struct FlagPush {
  vec3 origin;   // camera position (orthographic: the ray origin of supersample (0, 0))
  int out_x0;    // the flag buffer's first pixel column (a multiple of 4)
  vec3 dir00;    // ray direction through supersample (0, 0)
  int out_y0;    // the flag buffer's first row
  vec4 du;       // direction (orthographic: origin) step per supersample to the right;
                 // orthographic: w = the view's height, the depth rule's scale
  vec4 dv;       // direction (orthographic: origin) step per supersample downwards
  ivec4 tile;    // pixel x0, y0, width, height of this tile (x0 a multiple of 4)
  ivec4 frame;   // frame width, height in pixels, S, uints per flag buffer row
  vec4 limits;   // cos(normal angle threshold), relative distance threshold, material rule (1 on, 0 off),
                 // orthographic camera (1) or pinhole (0)
  ivec4 area;    // frame pixels x0, y0, width, height flagged by this dispatch (x0 % 4 == 0)
};

// Per-frame triangle planes (triangle_planes.comp).
struct PlanePush {
  vec4 origin;      // camera position
  ivec4 triangles;  // count, first triangle of this dispatch, 0, 0
};

#ifdef __cplusplus
static_assert(sizeof(RasterPush) == 112);  // within the 128-byte push-constant minimum
static_assert(sizeof(FlagPush) == 128);  // the 128-byte push-constant minimum
static_assert(offsetof(FlagPush, out_x0) == 12 && offsetof(FlagPush, out_y0) == 28);  // std430: an int after a vec3
static_assert(sizeof(PlanePush) <= sizeof(FlagPush));
}  // namespace zz::gpu
#endif

#endif  // ZZ_VISIBILITY_SHARED_H
