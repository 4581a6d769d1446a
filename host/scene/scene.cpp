#include "scene/scene.h"

#include <algorithm>

namespace zz {

std::vector<std::string> EffectSet::names() const {
  std::vector<std::string> out;
  if (shadows) out.push_back("shadows");
  if (reflection) out.push_back("reflection");
  if (refraction) out.push_back("refraction");
  if (absorption) out.push_back("absorption");
  if (textures) out.push_back("textures");
  if (emission) out.push_back("emission");
  if (material_textures) out.push_back("material_textures");
  if (normal_maps) out.push_back("normal_maps");
  if (alpha_mask) out.push_back("alpha_mask");
  if (alpha_blend) out.push_back("alpha_blend");
  if (shadow_transmission) out.push_back("shadow_transmission");
  return out;
}

void Scene::finalize_materials() {
  whitted.clear();
  whitted.reserve(materials.size());
  for (const Material& m : materials) whitted.push_back(whitted_from_gltf(m));
}

Scene::Bounds Scene::bounds() const {
  Bounds b;
  if (!positions.empty()) b.lo = b.hi = positions[0];
  for (const glm::vec3& p : positions) b.lo = glm::min(b.lo, p), b.hi = glm::max(b.hi, p);
  return b;
}

EffectSet Scene::effects() const {
  // Only materials some triangle uses count: an unused glass material in a file must not
  // switch on refraction code for a scene that has no glass on screen.
  std::vector<bool> used(materials.size(), false);
  for (uint32_t m : material_of)
    if (m < used.size()) used[m] = true;

  EffectSet e;
  e.shadows = !lights.empty();
  for (size_t i = 0; i < materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = materials[i];
    WhittedMaterial w = i < whitted.size() ? whitted[i] : whitted_from_gltf(m);
    auto valid = [&](const TextureRef& t) { return t.index >= 0 && size_t(t.index) < textures.size(); };
    if (valid(m.metallic_roughness_texture)) {
      // Textures only scale the factors down: the smoothest and most metallic texel decides
      // whether any hit on this material can mirror.
      float min_roughness = 1.0f, max_metallic = 0.0f;
      const Texture& tex = textures[size_t(m.metallic_roughness_texture.index)];
      for (size_t i = 0; i < tex.texel_count(); ++i) {
        const glm::vec4 t = tex.texel(i);
        min_roughness = std::min(min_roughness, t.g);
        max_metallic = std::max(max_metallic, t.b);
      }
      WhittedMaterial best = w;
      whitted_surface(best, {m.base_color, m.metallic * max_metallic, m.roughness * min_roughness, m.transmission});
      e.reflection |= best.reflects();
      e.material_textures = true;
    }
    e.material_textures |= valid(m.transmission_texture) && m.transmission > 0.0f;
    e.reflection |= w.reflects();
    e.refraction |= w.transmits();
    e.absorption |= w.transmits() && (w.absorption.x > 0.0f || w.absorption.y > 0.0f ||
                                      w.absorption.z > 0.0f);
    e.textures |= valid(m.base_color_texture) || valid(m.emissive_texture) ||
                  valid(m.metallic_roughness_texture) || valid(m.transmission_texture);
    e.normal_maps |= valid(m.normal_texture) && tangents.size() == positions.size();
    e.textures |= e.normal_maps;
    e.alpha_mask |= m.alpha_mode == AlphaMode::Mask;
    e.alpha_blend |= m.alpha_mode == AlphaMode::Blend;
    // glTF emission = emissiveFactor * texture, so a zero factor emits nothing.
    e.emission |= w.emission.x > 0.0f || w.emission.y > 0.0f || w.emission.z > 0.0f;
  }
  e.shadow_transmission = e.shadows && e.refraction;
  return e;
}

}  // namespace zz
