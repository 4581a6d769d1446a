// What a material is at one surface point, shared by the shader (render/shader.cpp) and the
// texture footprint correction (render/texture_detail.cpp), so both see the same albedo:
// the point's texture coordinates, and the Whitted material with the textures applied.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "scene/materials.h"
#include "scene/scene.h"

namespace zz {

// TEXCOORD_0 and TEXCOORD_1 of a point (TEXCOORD_1 = TEXCOORD_0 where the mesh has none).
struct Texcoords {
  glm::vec2 uv0{0.0f}, uv1{0.0f};
  Texcoords() = default;
  Texcoords(glm::vec2 first, glm::vec2 second) : uv0(first), uv1(second) {}
  // At barycentrics (u, v) of the triangle at t3 (its first vertex index).
  Texcoords(const Scene& scene, size_t t3, float u, float v) {
    const float w = 1.0f - u - v;
    uv0 = w * scene.uvs[t3] + u * scene.uvs[t3 + 1] + v * scene.uvs[t3 + 2];
    uv1 = scene.uvs1.empty() ? uv0 : w * scene.uvs1[t3] + u * scene.uvs1[t3 + 1] + v * scene.uvs1[t3 + 2];
  }
  glm::vec4 sample(const Scene& scene, const TextureRef& ref) const {
    return scene.textures[size_t(ref.index)].sample(ref.at(uv0, uv1));
  }
};

// The Whitted material of material `index` at `tc`: the material's own, or (textured
// metallic, roughness, transmission, or a base texture that tints mirror or glass)
// evaluated into `local`. `albedo` receives the diffuse reflectance with the base texture
// applied.
inline const WhittedMaterial& textured_material(const Scene& scene, uint32_t index, const Texcoords& tc,
                                                WhittedMaterial& local, glm::vec3& albedo) {
  const WhittedMaterial& w = scene.whitted[index];
  const Material& m = scene.materials[index];
  glm::vec4 base(1.0f);
  if (m.base_color_texture.used()) base = tc.sample(scene, m.base_color_texture);
  if (!m.varies_per_hit()) {
    albedo = w.diffuse * glm::vec3(base);
    return w;
  }
  PbrSample p{m.base_color * glm::vec3(base), m.metallic, m.roughness, m.transmission};
  if (m.metallic_roughness_texture.used()) {  // glTF: G = roughness, B = metallic
    const glm::vec4 mr = tc.sample(scene, m.metallic_roughness_texture);
    p.roughness *= mr.g;
    p.metallic *= mr.b;
  }
  if (m.transmission_texture.used()) p.transmission *= tc.sample(scene, m.transmission_texture).r;
  local = w;
  whitted_surface(local, p);
  albedo = local.diffuse;
  return local;
}

// glTF coverage at a point: 1 opaque; MASK gives 0 or 1 by the cutoff; BLEND the alpha.
inline float coverage(const Scene& scene, const Material& m, const Texcoords& tc) {
  if (m.alpha_mode == AlphaMode::Opaque) return 1.0f;
  float a = m.base_alpha;
  if (m.base_color_texture.used()) a *= tc.sample(scene, m.base_color_texture).a;
  if (m.alpha_mode == AlphaMode::Mask) return a >= m.alpha_cutoff ? 1.0f : 0.0f;
  return std::clamp(a, 0.0f, 1.0f);
}

// The Whitted material at a hit, as textured_material; untextured kernels skip the lookups.
template <bool kTextured>
const WhittedMaterial& material_at(const Scene& scene, uint32_t index, const Texcoords* tc, WhittedMaterial& local,
                                   glm::vec3& albedo) {
  if constexpr (kTextured) return textured_material(scene, index, *tc, local, albedo);
  albedo = scene.whitted[index].diffuse;
  return scene.whitted[index];
}

}  // namespace zz
