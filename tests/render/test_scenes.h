// Small scenes built in code for the render tests.
#pragma once

#include <glm/glm.hpp>

#include <cmath>

#include "scene/scene.h"

namespace zz::test {

inline void add_triangle(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, uint32_t material) {
  const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
  s.positions.insert(s.positions.end(), {a, b, c});
  s.normals.insert(s.normals.end(), {n, n, n});
  s.uvs.insert(s.uvs.end(), {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1)});
  s.material_of.push_back(material);
}

// Quad a-b-c-d (counter-clockwise seen from the side its normal points to).
inline void add_quad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, uint32_t material) {
  add_triangle(s, a, b, c, material);
  add_triangle(s, a, c, d, material);
}

// Axis-aligned box as 12 outward-facing triangles.
inline void add_box(Scene& s, glm::vec3 lo, glm::vec3 hi, uint32_t material) {
  const glm::vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                          {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  add_quad(s, p[0], p[3], p[2], p[1], material);  // -z
  add_quad(s, p[4], p[5], p[6], p[7], material);  // +z
  add_quad(s, p[0], p[1], p[5], p[4], material);  // -y
  add_quad(s, p[3], p[7], p[6], p[2], material);  // +y
  add_quad(s, p[0], p[4], p[7], p[3], material);  // -x
  add_quad(s, p[1], p[2], p[6], p[5], material);  // +x
}

// A unit UV sphere at the origin of `segments` x `rings` quads, poles on y, turned by
// `turn` radians about y; smooth shading (vertex normals are the sphere's).
inline void add_uv_sphere(Scene& s, int segments, int rings, float turn, uint32_t material) {
  const float pi = 3.14159265358979f;
  auto at = [&](int i, int j) {
    const float phi = 2.0f * pi * float(i) / float(segments) + turn, theta = pi * float(j) / float(rings);
    return glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
  };
  auto tri = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    if (glm::length(glm::cross(b - a, c - a)) < 1e-6f) return;  // the poles' degenerate halves
    s.positions.insert(s.positions.end(), {a, b, c});
    s.normals.insert(s.normals.end(), {glm::normalize(a), glm::normalize(b), glm::normalize(c)});
    s.uvs.insert(s.uvs.end(), {glm::vec2(0), glm::vec2(0), glm::vec2(0)});
    s.material_of.push_back(material);
  };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {  // outward winding
      tri(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      tri(at(i, j), at(i + 1, j), at(i + 1, j + 1));
    }
}

inline Material diffuse_material(glm::vec3 albedo) {
  Material m;
  m.base_color = albedo;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  return m;
}

// A perfect metal mirror: F0 = `reflectance`, no diffuse, a highlight of exponent 10000.
inline Material mirror_material(glm::vec3 reflectance) {
  Material m;
  m.base_color = reflectance;
  m.metallic = 1.0f;
  m.roughness = 0.0f;
  return m;
}

// Solid glass (KHR_materials_volume thickness > 0): it bends light; without a thickness a
// transmissive surface is a thin wall.
inline Material glass_material(float ior) {
  Material m;
  m.base_color = glm::vec3(1.0f);
  m.roughness = 0.0f;
  m.transmission = 1.0f;
  m.ior = ior;
  m.thickness = 1.0f;
  return m;
}

// A 20x20 floor in the z = 0 plane facing +z, a camera 4 units above looking down.
inline Scene lit_floor(float albedo, float light_intensity, float light_height) {
  Scene s;
  s.name = "lit_floor";
  s.materials.push_back(diffuse_material(glm::vec3(albedo)));
  add_quad(s, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 0);
  Light light;
  light.position = {0, 0, light_height};
  light.intensity = glm::vec3(light_intensity);
  s.lights.push_back(light);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.max_depth = 2;
  s.finalize_materials();
  return s;
}

}  // namespace zz::test
