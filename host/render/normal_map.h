// glTF normal maps: the tangent frame a texel is applied in, shared by the shader
// (render/shader.cpp) and the texture footprint correction (render/texture_detail.cpp).
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstddef>

#include "scene/scene.h"

namespace zz {

// The interpolated vertex normal at barycentrics (u, v) of the triangle at t3 (its first
// vertex index), unit; `fallback` (the geometric normal) where it degenerates.
inline glm::vec3 interpolated_normal(const Scene& scene, size_t t3, float u, float v, glm::vec3 fallback) {
  const float w = 1.0f - u - v;
  const glm::vec3 ns = w * scene.normals[t3] + u * scene.normals[t3 + 1] + v * scene.normals[t3 + 2];
  const float ns_len = glm::length(ns);
  return ns_len > 0.0f && std::isfinite(ns_len) ? ns / ns_len : fallback;
}

// The frame (tangent t, bitangent b, normal n) at (u, v) of the triangle at t3 whose
// interpolated normal is n: t the vertex tangents' interpolation made orthogonal to n, b =
// n x t times the handedness. False where there is none (no tangents, no UVs).
inline bool normal_map_frame(const Scene& scene, size_t t3, float u, float v, glm::vec3 n, glm::vec3 frame[3]) {
  if (scene.tangents.empty()) return false;
  const float w = 1.0f - u - v;
  const glm::vec4 t4 = w * scene.tangents[t3] + u * scene.tangents[t3 + 1] + v * scene.tangents[t3 + 2];
  glm::vec3 t = glm::vec3(t4) - n * glm::dot(n, glm::vec3(t4));
  const float len = glm::length(t);
  if (!(len > 1e-12f) || !std::isfinite(len)) return false;
  t /= len;
  frame[0] = t;
  frame[1] = glm::cross(n, t) * (t4.w < 0.0f ? -1.0f : 1.0f);
  frame[2] = n;
  return true;
}

// The normal of a normal-map texel (its RGB in [0, 1]) in `frame`, x and y scaled by the
// material's normalTexture.scale; `fallback` where it degenerates.
inline glm::vec3 mapped_in_frame(const glm::vec3 frame[3], glm::vec3 rgb, float scale, glm::vec3 fallback) {
  const glm::vec3 texel = rgb * 2.0f - 1.0f;
  const glm::vec3 mapped = frame[0] * (texel.x * scale) + frame[1] * (texel.y * scale) + frame[2] * texel.z;
  const float mapped_len = glm::length(mapped);
  return mapped_len > 1e-12f && std::isfinite(mapped_len) ? mapped / mapped_len : fallback;
}

}  // namespace zz
