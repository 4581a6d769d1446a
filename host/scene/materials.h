// Materials: the glTF PBR parameters as loaded, and their Whitted interpretation.
// The mapping from glTF metallic/roughness to Whitted coefficients lives only in
// whitted_from_gltf() (materials.cpp), documented there.
#pragma once

#include <glm/glm.hpp>

#include <limits>
#include <string>

namespace zz {

// glTF 2.0 metallic-roughness material + the extensions we read.
struct Material {
  std::string name;
  glm::vec3 base_color{0.8f};
  int base_color_texture = -1;  // index into Scene::textures, sampled at TEXCOORD_0
  float metallic = 0.0f;
  float roughness = 1.0f;
  glm::vec3 emissive{0.0f};
  int emissive_texture = -1;
  float transmission = 0.0f;  // KHR_materials_transmission
  float ior = 1.5f;           // KHR_materials_ior
  // KHR_materials_volume: Beer-Lambert attenuation inside the closed surface.
  glm::vec3 attenuation_color{1.0f};
  float attenuation_distance = std::numeric_limits<float>::infinity();
  bool double_sided = false;
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
  glm::vec3 absorption{0.0f};     // Beer-Lambert sigma_a per unit length inside (0 = clear)
  glm::vec3 emission{0.0f};

  bool reflects() const { return mirror.x > 0.0f || mirror.y > 0.0f || mirror.z > 0.0f; }
  bool transmits() const {
    return transmission.x > 0.0f || transmission.y > 0.0f || transmission.z > 0.0f;
  }
};

// Roughness at and above which a surface is treated as not a mirror.
inline constexpr float kMirrorRoughnessLimit = 0.2f;

WhittedMaterial whitted_from_gltf(const Material& m);

}  // namespace zz
