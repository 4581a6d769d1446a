// Materials: the glTF PBR parameters as loaded, and their Whitted interpretation.
// The mapping from glTF metallic/roughness to Whitted coefficients lives only in
// whitted_surface() / whitted_from_gltf() (materials.cpp), documented there.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace zz {

// One texture slot of a material (glTF textureInfo): which texture, which TEXCOORD set,
// and the KHR_texture_transform applied to that set's coordinates.
struct TextureRef {
  int index = -1;             // into Scene::textures; -1 = no texture
  int texcoord = 0;           // TEXCOORD_<n>; 0 or 1
  glm::mat3 transform{1.0f};  // uv' = transform * (uv, 1)
  bool transformed = false;   // transform is not the identity

  bool used() const { return index >= 0; }
  glm::vec2 apply(glm::vec2 uv) const { return transformed ? glm::vec2(transform * glm::vec3(uv, 1.0f)) : uv; }
  // The texture's coordinates at a point with TEXCOORD_0 `uv0` and TEXCOORD_1 `uv1`.
  glm::vec2 at(glm::vec2 uv0, glm::vec2 uv1) const { return apply(texcoord == 1 ? uv1 : uv0); }
};

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

// glTF 2.0 metallic-roughness material + the extensions we read.
// normalTexture.scale is held within +-this: beyond it a texel's z is under float's
// resolution beside its x and y, so a larger scale gives the same normals, and from about
// 1e19 their squared lengths overflow (the map was silently dropped there).
inline constexpr float kNormalScaleLimit = 1e15f;

struct Material {
  std::string name;
  glm::vec3 base_color{0.8f};
  float base_alpha = 1.0f;             // baseColorFactor[3]
  TextureRef base_color_texture;       // sRGB; alpha in A
  float metallic = 0.0f;
  float roughness = 1.0f;
  TextureRef metallic_roughness_texture;  // linear; G = roughness, B = metallic
  glm::vec3 emissive{0.0f};
  TextureRef emissive_texture;
  TextureRef normal_texture;           // linear tangent-space normal, +Y = image up
  float normal_scale = 1.0f;           // within +-kNormalScaleLimit
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  float transmission = 0.0f;           // KHR_materials_transmission
  TextureRef transmission_texture;     // linear; R = transmission
  float ior = 1.5f;                    // KHR_materials_ior
  // KHR_materials_volume: a solid (thickness > 0) with Beer-Lambert attenuation inside
  // its closed surface. Without it, or at thickness 0 (the default), transmission is
  // thin-walled: the surface is a sheet, light crosses it unbent and unabsorbed.
  float thickness = 0.0f;
  glm::vec3 attenuation_color{1.0f};
  float attenuation_distance = std::numeric_limits<float>::infinity();
  bool double_sided = false;

  // The Whitted coefficients depend on the hit point (textured metallic, roughness or
  // transmission, or a base colour texture that tints a mirror or the glass), not only
  // the diffuse albedo.
  bool varies_per_hit() const {
    return metallic_roughness_texture.used() || transmission_texture.used() ||
           (base_color_texture.used() && (metallic > 0.0f || transmission > 0.0f));
  }
  bool see_through() const { return alpha_mode != AlphaMode::Opaque; }
  // Every texture slot, used or not.
  std::array<const TextureRef*, 5> texture_slots() const {
    return {&base_color_texture, &metallic_roughness_texture, &transmission_texture, &emissive_texture,
            &normal_texture};
  }
};

// What the Whitted shader uses. All colours linear RGB.
struct WhittedMaterial {
  glm::vec3 diffuse{0.0f};        // Lambert albedo (multiplied by the base texture)
  glm::vec3 specular{0.0f};       // Phong highlight colour per light
  float shininess = 1.0f;         // Phong exponent
  glm::vec3 mirror{0.0f};         // reflectance of the perfect mirror ray at normal incidence
  bool fresnel_mirror = false;    // dielectric: mirror weight follows Schlick with F0 = mirror
  glm::vec3 transmission{0.0f};   // tint of the refracted ray (0 = opaque)
  float ior = 1.5f;
  bool thin_walled = true;        // transmission through a sheet: unbent, Fresnel from the IOR only
  glm::vec3 absorption{0.0f};     // Beer-Lambert sigma_a per unit length inside (0 = clear)
  glm::vec3 emission{0.0f};

  bool reflects() const { return mirror.x > 0.0f || mirror.y > 0.0f || mirror.z > 0.0f; }
  bool transmits() const {
    return transmission.x > 0.0f || transmission.y > 0.0f || transmission.z > 0.0f;
  }
};

// Whether what a camera sees on the surface is mostly an image of something else: it
// refracts, or it is a mirror (not a dielectric's Fresnel reflection) that reflects at
// least half the light.
inline bool shows_an_image(const WhittedMaterial& m) {
  const float reflectance = std::max(m.mirror.x, std::max(m.mirror.y, m.mirror.z));
  return m.transmits() || (!m.fresnel_mirror && reflectance >= 0.5f);
}

// The same for a glTF material: also an alpha-BLEND surface that lets more than half the
// light through. Its coverage is base_alpha times a texture's alpha, at most base_alpha,
// so a factor below 1/2 bounds it everywhere.
inline bool shows_an_image(const Material& gltf, const WhittedMaterial& m) {
  return shows_an_image(m) || (gltf.alpha_mode == AlphaMode::Blend && gltf.base_alpha < 0.5f);
}

// Roughness at and above which a surface is treated as not a mirror.
inline constexpr float kMirrorRoughnessLimit = 0.2f;

// The glTF inputs at one surface point: factors times texture values.
struct PbrSample {
  glm::vec3 base_color;
  float metallic;
  float roughness;
  float transmission;
};

// Sets the surface terms of `w` (diffuse, specular, shininess, mirror, transmission) from
// one point's inputs; ior, absorption and emission are left as they are. Cheap (no
// transcendental functions): the shader calls it per hit for materials that vary.
void whitted_surface(WhittedMaterial& w, const PbrSample& p);

// The whole Whitted material from the glTF factors alone.
WhittedMaterial whitted_from_gltf(const Material& m);

// A factor of a material outside the range glTF gives it: what ("metallic -0.5 outside
// [0, 1]") and what whitted_from_gltf does with it instead ("clamped").
struct FactorProblem {
  std::string what, remedy;
  std::string text() const { return what + ", " + remedy; }
};

// The factors of `m` outside glTF's ranges: a glTF's are warned about, a rig's refused.
std::vector<FactorProblem> out_of_range_factors(const Material& m);

}  // namespace zz
