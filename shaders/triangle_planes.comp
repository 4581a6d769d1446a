#version 450
// Per frame, per triangle: the unit geometric normal and the camera-relative plane offset
// h = n.(v0 - o), the per-triangle half of geo_flags.comp's distance test, so that pass
// reads one vec4 per id instead of a normal, a vertex and a subtraction per sample pair.
#extension GL_GOOGLE_include_directive : require
#include "visibility_shared.h"

layout(local_size_x = ZZ_PLANE_GROUP) in;

layout(push_constant) uniform Push { PlanePush p; };
layout(std430, binding = ZZ_BIND_FIRST_VERTICES) readonly buffer FirstVertices { vec4 first_vertices[]; };
layout(std430, binding = ZZ_BIND_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = ZZ_BIND_PLANES) writeonly buffer Planes { vec4 planes[]; };

precise float dot3(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y;
  r = r + a.z * b.z;
  return r;
}

void main() {
  // Dispatches hold at most maxComputeWorkGroupCount[0] groups: a large scene takes several.
  uint t = uint(p.triangles.y) + gl_GlobalInvocationID.x;
  if (t >= uint(p.triangles.x)) return;
  vec3 n = normals[t].xyz;
  precise float h = dot3(n, first_vertices[t].xyz - p.origin.xyz);
  planes[t] = vec4(n, h);
}
