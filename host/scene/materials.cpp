#include "scene/materials.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace zz {

// The Whitted interpretation of a glTF material (the one place it is defined):
// - F0 = mix(F0_ior, base, metallic): the normal-incidence reflectance of the glTF BRDF
//   (F0_ior = ((ior - 1) / (ior + 1))^2, 0.04 for the default ior 1.5).
// - Mirror reflection only for near-mirror surfaces: weight s = 1 - roughness / 0.2,
//   clamped to [0,1] (a rough surface has no coherent reflection to trace). Metals reflect
//   F0 * s; dielectrics reflect with Schlick's Fresnel from F0_ior, applied per ray at
//   shading time.
// - Diffuse = base * (1 - metallic) * (1 - transmission): energy that is neither mirrored
//   by metal nor transmitted.
// - Highlight: Phong exponent from the GGX alpha = roughness^2, n = 2/alpha^2 - 2
//   (the Blinn-Phong/Beckmann correspondence), colour F0; glossier = sharper.
// - Transmission = base * transmission * (1 - metallic), bent with the IOR; the surface
//   then also mirrors with the dielectric Fresnel, whatever its roughness.
// - Volume: a solid only with KHR_materials_volume's thickness > 0; then it bends and
//   absorbs, sigma_a = -ln(attenuation_color) / attenuation_distance (glTF spec). Else
//   the surface is thin-walled: transmitted light goes straight on, unabsorbed.
void whitted_surface(WhittedMaterial& w, const PbrSample& p) {
  const float metallic = std::clamp(p.metallic, 0.0f, 1.0f);
  const float roughness = std::clamp(p.roughness, 0.0f, 1.0f);
  const float transmission = std::clamp(p.transmission, 0.0f, 1.0f) * (1.0f - metallic);
  const glm::vec3 base = glm::clamp(p.base_color, glm::vec3(0.0f), glm::vec3(1.0f));
  const float ior = w.ior;
  const float f0_dielectric = ((ior - 1.0f) / (ior + 1.0f)) * ((ior - 1.0f) / (ior + 1.0f));
  const glm::vec3 f0 = glm::mix(glm::vec3(f0_dielectric), base, metallic);

  const float smooth = std::clamp(1.0f - roughness / kMirrorRoughnessLimit, 0.0f, 1.0f);
  w.diffuse = base * (1.0f - metallic) * (1.0f - transmission);
  w.specular = f0;
  const float alpha = std::max(roughness * roughness, 1e-3f);
  w.shininess = std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 10000.0f);

  w.transmission = glm::vec3(0.0f);
  w.mirror = glm::vec3(0.0f);
  w.fresnel_mirror = false;
  if (transmission > 0.0f) {
    w.transmission = base * transmission;
    w.mirror = glm::vec3(f0_dielectric);
    w.fresnel_mirror = true;
  } else if (metallic > 0.0f && smooth > 0.0f) {
    w.mirror = f0 * smooth * metallic;
    if (metallic < 1.0f) w.mirror += glm::vec3(f0_dielectric * smooth * (1.0f - metallic));
  } else if (smooth > 0.0f) {
    w.mirror = glm::vec3(f0_dielectric * smooth);
    w.fresnel_mirror = true;
  }
}

WhittedMaterial whitted_from_gltf(const Material& m) {
  WhittedMaterial w;
  w.ior = std::isfinite(m.ior) && m.ior >= 1.0f ? m.ior : 1.5f;
  w.thin_walled = !(m.thickness > 0.0f);
  whitted_surface(w, {m.base_color, m.metallic, m.roughness, m.transmission});
  if (!w.thin_walled && std::isfinite(m.attenuation_distance) && m.attenuation_distance > 0.0f) {
    glm::vec3 c = glm::clamp(m.attenuation_color, glm::vec3(1e-6f), glm::vec3(1.0f));
    w.absorption = -glm::log(c) / m.attenuation_distance;
  }
  w.emission = glm::clamp(m.emissive, glm::vec3(0.0f), glm::vec3(1e30f));  // out_of_range_factors names both
  return w;
}

std::vector<FactorProblem> out_of_range_factors(const Material& m) {
  std::vector<FactorProblem> found;
  auto text = [](float v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", double(v));
    return std::string(b);
  };
  auto colour_text = [](glm::vec3 c) {
    char b[96];
    std::snprintf(b, sizeof b, "(%g, %g, %g)", double(c.x), double(c.y), double(c.z));
    return std::string(b);
  };
  auto unit = [&](const char* name, float v) {
    if (v < 0.0f || v > 1.0f) found.push_back({std::string(name) + " " + text(v) + " outside [0, 1]", "clamped"});
  };
  auto unit_colour = [&](const char* name, glm::vec3 c) {
    if (glm::any(glm::lessThan(c, glm::vec3(0.0f))) || glm::any(glm::greaterThan(c, glm::vec3(1.0f))))
      found.push_back({std::string(name) + " " + colour_text(c) + " outside [0, 1]", "clamped"});
  };
  unit_colour("base colour", m.base_color);
  unit("alpha", m.base_alpha);
  unit("metallic", m.metallic);
  unit("roughness", m.roughness);
  unit("transmission", m.transmission);
  unit_colour("attenuation colour", m.attenuation_color);
  if (glm::any(glm::lessThan(m.emissive, glm::vec3(0.0f))))
    found.push_back({"emissive " + colour_text(m.emissive) + " below 0", "clamped"});
  // Where the shader's radiance stops (render/shader.cpp) and a light's intensity does.
  if (glm::any(glm::greaterThan(m.emissive, glm::vec3(1e30f))))
    found.push_back({"emissive " + colour_text(m.emissive) + " above 1e30", "clamped to 1e30"});
  // KHR_materials_ior allows 0, a Fresnel term of 1 for converted specular-glossiness
  // materials, whose KHR_materials_specular zigzag does not read: 0 alone would make every
  // such material a white mirror.
  if (m.ior == 0.0f)
    found.push_back({"ior 0 (specular-glossiness's full Fresnel, for KHR_materials_specular, which zigzag does not support)",
                     "1.5 used"});
  else if (!(m.ior >= 1.0f)) found.push_back({"ior " + text(m.ior) + " below 1", "1.5 used"});
  if (m.thickness < 0.0f) found.push_back({"thickness " + text(m.thickness) + " below 0", "thin-walled, as 0"});
  if (!(m.attenuation_distance > 0.0f))
    found.push_back({"attenuation distance " + text(m.attenuation_distance) + " not > 0", "no absorption"});
  return found;
}

}  // namespace zz
