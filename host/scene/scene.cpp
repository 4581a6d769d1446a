#include "scene/scene.h"

namespace zz {

std::vector<std::string> EffectSet::names() const {
  std::vector<std::string> out;
  if (shadows) out.push_back("shadows");
  if (reflection) out.push_back("reflection");
  if (refraction) out.push_back("refraction");
  if (absorption) out.push_back("absorption");
  if (textures) out.push_back("textures");
  if (emission) out.push_back("emission");
  return out;
}

void Scene::finalize_materials() {
  whitted.clear();
  whitted.reserve(materials.size());
  for (const Material& m : materials) whitted.push_back(whitted_from_gltf(m));
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
    e.reflection |= w.reflects();
    e.refraction |= w.transmits();
    e.absorption |= w.transmits() && (w.absorption.x > 0.0f || w.absorption.y > 0.0f ||
                                      w.absorption.z > 0.0f);
    auto valid = [&](int t) { return t >= 0 && size_t(t) < textures.size(); };
    e.textures |= valid(m.base_color_texture) || valid(m.emissive_texture);
    // glTF emission = emissiveFactor * texture, so a zero factor emits nothing.
    e.emission |= w.emission.x > 0.0f || w.emission.y > 0.0f || w.emission.z > 0.0f;
  }
  return e;
}

}  // namespace zz
