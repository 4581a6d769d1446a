#version 450
// Visibility raster: world-space triangles, non-indexed, 3 vertices per triangle.
// Built twice: as is, and with ZZ_CLIP_PLANES for a camera whose near/far planes cut into
// the scene (host/gpu/visibility.cpp), which clips at them as the camera rays do.
#extension GL_GOOGLE_include_directive : require
#include "visibility_shared.h"

layout(push_constant) uniform Push { RasterPush p; };

layout(location = 0) in vec3 position;
layout(location = 0) flat out uint triangle_id;

#ifdef ZZ_CLIP_PLANES
out gl_PerVertex {
  vec4 gl_Position;
  float gl_ClipDistance[2];
};
#endif

void main() {
  gl_Position = p.clip_from_view * vec4(position - p.origin.xyz, 1.0);
#ifdef ZZ_CLIP_PLANES
  // Depth along the view direction, as scene/camera.h CameraClip::depth: linear in the
  // position, so the clipper's interpolation is exact up to rounding.
  const float depth = dot(position - p.origin.xyz, p.clip_forward.xyz);
  gl_ClipDistance[0] = depth - p.clip_planes.x;
  gl_ClipDistance[1] = p.clip_planes.y - depth;
#endif
  // Triangle index + 1, so 0 stays "background"; same numbering as Scene and the BVH.
  triangle_id = uint(gl_VertexIndex) / 3u + 1u;
}
