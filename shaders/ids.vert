#version 450
// Visibility raster: world-space triangles, non-indexed, 3 vertices per triangle.
#extension GL_GOOGLE_include_directive : require
#include "visibility_shared.h"

layout(push_constant) uniform Push { RasterPush p; };

layout(location = 0) in vec3 position;
layout(location = 0) flat out uint triangle_id;

void main() {
  gl_Position = p.clip_from_view * vec4(position - p.origin.xyz, 1.0);
  // Triangle index + 1, so 0 stays "background"; same numbering as Scene and the BVH.
  triangle_id = uint(gl_VertexIndex) / 3u + 1u;
}
