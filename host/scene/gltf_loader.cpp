// glTF 2.0 -> Scene: flattens the default scene's node hierarchy into world-space
// triangles, and reads materials, textures, KHR_lights_punctual lights and cameras.
#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "core/error.h"
#include "core/file_io.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_file.h"
#include "scene/gltf_image.h"
#include "scene/loader.h"

namespace zz {
namespace {

// The extensions a file may require (extensionsRequired) and still load: those this loader
// reads, and KHR_mesh_quantization, whose integer attributes read_floats converts.
const std::vector<std::string> kSupportedExtensions = {
    "KHR_lights_punctual",       "KHR_materials_emissive_strength", "KHR_materials_ior",
    "KHR_materials_transmission", "KHR_materials_volume",            "KHR_mesh_quantization",
    "KHR_texture_transform"};

// ---- tinygltf::Value helpers (Value::Get asserts on the wrong type) ------------------
const tinygltf::Value* member(const tinygltf::Value& v, const char* key) {
  if (!v.IsObject() || !v.Has(key)) return nullptr;
  return &v.Get(key);
}
const tinygltf::Value* extension(const tinygltf::ExtensionMap& ext, const char* name) {
  auto it = ext.find(name);
  return it == ext.end() || !it->second.IsObject() ? nullptr : &it->second;
}
float number(const tinygltf::Value* obj, const char* key, float fallback) {
  const tinygltf::Value* v = obj ? member(*obj, key) : nullptr;
  return v && v->IsNumber() ? float(v->GetNumberAsDouble()) : fallback;
}
glm::vec3 vec3_of(const tinygltf::Value* obj, const char* key, glm::vec3 fallback) {
  const tinygltf::Value* v = obj ? member(*obj, key) : nullptr;
  if (!v || v->ArrayLen() < 3) return fallback;
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v->Get(i).IsNumber()) return fallback;
    out[i] = float(v->Get(i).GetNumberAsDouble());
  }
  return out;
}
glm::vec3 vec3_of(const std::vector<double>& v, glm::vec3 fallback) {
  return v.size() >= 3 ? glm::vec3(float(v[0]), float(v[1]), float(v[2])) : fallback;
}
bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// A rotation times a uniform positive scale, within float rounding of the node's matrix:
// a camera there sees what an orthonormal frame sees.
bool is_rotation_times_scale(const glm::mat3& m) {
  const float lx = glm::length(m[0]), ly = glm::length(m[1]), lz = glm::length(m[2]);
  constexpr float kTolerance = 1e-5f;
  const auto near = [&](float a, float b) { return std::abs(a - b) <= kTolerance * std::max(a, b); };
  return near(lx, lz) && near(ly, lz) && std::abs(glm::dot(m[0], m[1])) <= kTolerance * lx * ly &&
         std::abs(glm::dot(m[1], m[2])) <= kTolerance * ly * lz && std::abs(glm::dot(m[0], m[2])) <= kTolerance * lx * lz &&
         glm::determinant(m) > 0.0f;
}

// The coordinates a normal texture is read at, for its tangent frame: its KHR_texture_transform
// turns the image against the UV set (the Khronos sample viewer builds the frame from them
// too). A transform that only scales evenly and shifts leaves the frame as it is, so the UV
// set is used untouched.
std::vector<float> normal_map_uvs(const TextureRef& ref, const std::vector<float>& uv) {
  const glm::mat2 linear(ref.transform);
  const bool turns = linear[0][1] != 0.0f || linear[1][0] != 0.0f || linear[0][0] != linear[1][1] || !(linear[0][0] > 0.0f);
  if (!ref.transformed || !turns) return uv;
  std::vector<float> out(uv.size());
  for (size_t i = 0; i + 1 < uv.size(); i += 2) {
    const glm::vec2 t = linear * glm::vec2(uv[i], uv[i + 1]);
    out[i] = t.x;
    out[i + 1] = t.y;
  }
  return out;
}

// Per-vertex tangents (xyz, w = bitangent sign) from the UV gradients of the triangles
// around each vertex (Lengyel 2001, "Computing Tangent Space Basis Vectors"), in the
// mesh's own frame. Not MikkTSpace: the frame is the area-weighted average over a vertex's
// triangles, so normal maps baked with MikkTSpace match only where the UV layout is smooth.
// glTF's v axis points down the image while normal maps' +Y points up it, hence the bitangent
// is -dP/dv: w = +1 when cross(N, T) is opposite to dP/dv.
std::vector<float> uv_gradient_tangents(const std::vector<float>& pos, const std::vector<float>& nrm,
                                        const std::vector<float>& uv, const std::vector<uint32_t>& tri) {
  const size_t vertices = pos.size() / 3;
  std::vector<float> out(vertices * 4, 0.0f);
  if (uv.empty()) return out;
  std::vector<glm::vec3> dpdu(vertices, glm::vec3(0.0f)), dpdv(vertices, glm::vec3(0.0f));
  std::vector<glm::vec3> face(vertices, glm::vec3(0.0f));  // the normal when the mesh has none
  auto p = [&](uint32_t i) { return glm::vec3(pos[i * 3], pos[i * 3 + 1], pos[i * 3 + 2]); };
  auto t = [&](uint32_t i) { return glm::vec2(uv[i * 2], uv[i * 2 + 1]); };
  for (size_t k = 0; k + 2 < tri.size(); k += 3) {
    const uint32_t a = tri[k], b = tri[k + 1], c = tri[k + 2];
    const glm::vec3 e1 = p(b) - p(a), e2 = p(c) - p(a);
    const glm::vec2 d1 = t(b) - t(a), d2 = t(c) - t(a);
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (!(std::abs(det) > 1e-20f)) continue;
    // Solve e1 = d1.x T + d1.y B, e2 = d2.x T + d2.y B; weighting by |det| keeps the sum
    // area-weighted and the orientation independent of the UV winding.
    const float sign = det > 0.0f ? 1.0f : -1.0f;
    const glm::vec3 tu = (e1 * d2.y - e2 * d1.y) * sign, tv = (e2 * d1.x - e1 * d2.x) * sign;
    for (uint32_t v : {a, b, c}) {
      face[v] += glm::cross(e1, e2);
      dpdu[v] += tu;
      dpdv[v] += tv;
    }
  }
  for (size_t v = 0; v < vertices; ++v) {
    glm::vec3 n = nrm.empty() ? face[v] : glm::vec3(nrm[v * 3], nrm[v * 3 + 1], nrm[v * 3 + 2]);
    if (glm::length(n) > 0.0f) n = glm::normalize(n);
    glm::vec3 tv = dpdu[v] - n * glm::dot(n, dpdu[v]);
    const float len = glm::length(tv);
    if (!(len > 0.0f) || !std::isfinite(len)) continue;
    tv /= len;
    const float w = glm::length(n) > 0.0f && glm::dot(glm::cross(n, tv), dpdv[v]) > 0.0f ? -1.0f : 1.0f;
    out[v * 4] = tv.x, out[v * 4 + 1] = tv.y, out[v * 4 + 2] = tv.z, out[v * 4 + 3] = w;
  }
  return out;
}

// Beyond this a triangle's coordinates are dropped: the watertight test multiplies two
// of them (edge functions), and their product must stay within float's range (3.4e38).
constexpr float kMaxCoordinate = 1e18f;

struct Loader {
  const tinygltf::Model& model;
  Scene& scene;
  const LoadOptions& options;
  std::string file;  // for messages
  uint32_t material_base = 0;
  int default_material = -1;
  // (image, srgb, wrap s, wrap t, filter) -> scene texture
  std::map<std::tuple<int, bool, TextureWrap, TextureWrap, TextureFilter>, int> texture_of_image;
  bool uses_texcoord1 = false;  // some texture slot reads TEXCOORD_1
  bool quantized = false;       // KHR_mesh_quantization: integer vertex attributes allowed
  Animation animation;  // sampled at options.time for every animated node

  void warn(const std::string& msg) const {
    if (!options.quiet) std::fprintf(stderr, "warning: %s: %s\n", file.c_str(), msg.c_str());
  }

  // Features the loader does not apply, said once per file: their absence changes the
  // image (a white mesh that the file colours, a bind pose), so it must not be silent.
  std::set<std::string> unsupported_said;
  void warn_unsupported(const std::string& feature, const std::string& msg) {
    if (unsupported_said.insert(feature).second) warn(msg);
  }
  static bool any_morph_weight(const std::vector<double>& weights) {
    return std::any_of(weights.begin(), weights.end(), [](double w) { return w != 0.0; });
  }

  // "material 'name'", or "material 3" (the file's index) for one without a name.
  std::string material_label(uint32_t scene_index) const {
    const std::string& name = scene.materials[scene_index].name;
    return name.empty() ? "material " + std::to_string(scene_index - material_base) : "material '" + name + "'";
  }

  void warn_out_of_range(uint32_t scene_index) const {
    std::string all;
    for (const FactorProblem& f : out_of_range_factors(scene.materials[scene_index])) all += (all.empty() ? "" : "; ") + f.text();
    if (!all.empty()) warn(material_label(scene_index) + ": " + all);
  }

  // A texture the file names but the loader cannot use: an error, unless the options allow
  // rendering without it.
  void texture_problem(const std::string& why) const {
    if (!options.allow_missing_textures)
      throw Error(file + ": " + why + " (--allow-missing-textures renders without it)");
    warn(why + ", rendered without it");
  }

  // Scene texture for glTF texture `index` with its sampler, decoded once per colour
  // space and sampler; -1 if unusable (with allow_missing_textures).
  int texture(int index, bool srgb) {
    if (index < 0 || size_t(index) >= model.textures.size()) {
      if (index >= 0) texture_problem("texture " + std::to_string(index) + " out of range");
      return -1;
    }
    const tinygltf::Texture& g = model.textures[size_t(index)];
    const int source = g.source;
    if (source < 0 || size_t(source) >= model.images.size()) {
      texture_problem("texture " + std::to_string(index) + " has no usable image source");
      return -1;
    }
    SamplerState sampler;
    if (g.sampler >= 0 && size_t(g.sampler) < model.samplers.size()) {
      const tinygltf::Sampler& gs = model.samplers[size_t(g.sampler)];
      const std::string where = "sampler " + std::to_string(g.sampler);
      sampler = {wrap_of(gs.wrapS, where + " wrapS"), wrap_of(gs.wrapT, where + " wrapT"),
                 gs.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? TextureFilter::Nearest : TextureFilter::Linear};
    } else if (g.sampler >= 0) {
      warn_unsupported("sampler " + std::to_string(g.sampler), "texture " + std::to_string(index) + ": sampler " +
                                                                   std::to_string(g.sampler) +
                                                                   " out of range, the default used (repeat, linear)");
    }
    auto key = std::make_tuple(source, srgb, sampler.wrap_s, sampler.wrap_t, sampler.filter);
    if (auto it = texture_of_image.find(key); it != texture_of_image.end()) return it->second;
    int result = -1;
    if (std::optional<Texture> t = decode(source, srgb)) {
      t->wrap_s = sampler.wrap_s;
      t->wrap_t = sampler.wrap_t;
      t->filter = sampler.filter;
      scene.textures.push_back(std::move(*t));
      result = int(scene.textures.size() - 1);
    }
    texture_of_image[key] = result;
    return result;
  }

  struct SamplerState {
    TextureWrap wrap_s = TextureWrap::Repeat, wrap_t = TextureWrap::Repeat;
    TextureFilter filter = TextureFilter::Linear;
  };
  TextureWrap wrap_of(int gl, const std::string& where) {
    if (gl == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::ClampToEdge;
    if (gl == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::MirroredRepeat;
    if (gl != TINYGLTF_TEXTURE_WRAP_REPEAT)
      warn_unsupported(where, where + " " + std::to_string(gl) + " is no glTF wrap mode (33071, 33648, 10497), repeat used");
    return TextureWrap::Repeat;
  }

  // A material's texture slot: texture, TEXCOORD set and KHR_texture_transform.
  TextureRef texture_ref(int index, int texcoord, const tinygltf::ExtensionMap& extensions, bool srgb) {
    TextureRef ref;
    if (index < 0) return ref;
    ref.index = texture(index, srgb);
    ref.texcoord = texcoord;
    if (const auto* e = extension(extensions, "KHR_texture_transform")) {
      ref.transform = texture_transform(*e);
      ref.transformed = ref.transform != glm::mat3(1.0f);
      if (const tinygltf::Value* t = member(*e, "texCoord"); t && t->IsNumber()) ref.texcoord = t->GetNumberAsInt();
    }
    if (ref.texcoord != 0 && ref.texcoord != 1) {
      warn("TEXCOORD_" + std::to_string(ref.texcoord) + " is not supported (0 and 1 are), TEXCOORD_0 used");
      ref.texcoord = 0;
    }
    if (ref.used() && ref.texcoord == 1) uses_texcoord1 = true;
    return ref;
  }
  // The same from an extension's JSON textureInfo object (e.g. transmissionTexture).
  TextureRef texture_ref(const tinygltf::Value* info, bool srgb) {
    const tinygltf::Value* index = info ? member(*info, "index") : nullptr;
    if (!index || !index->IsNumber()) return {};
    const tinygltf::Value* texcoord = member(*info, "texCoord");
    tinygltf::ExtensionMap extensions;
    if (const tinygltf::Value* e = member(*info, "extensions"); e && e->IsObject())
      for (const std::string& key : e->Keys()) extensions[key] = e->Get(key);
    return texture_ref(index->GetNumberAsInt(), texcoord && texcoord->IsNumber() ? texcoord->GetNumberAsInt() : 0,
                       extensions, srgb);
  }

  // KHR_texture_transform: uv' = T * R * S * uv with R = [[cos, sin], [-sin, cos]].
  static glm::mat3 texture_transform(const tinygltf::Value& e) {
    const tinygltf::Value* o = member(e, "offset");
    const tinygltf::Value* s = member(e, "scale");
    glm::vec2 offset(0.0f), scale(1.0f);
    if (o && o->ArrayLen() >= 2 && o->Get(0).IsNumber() && o->Get(1).IsNumber())
      offset = {float(o->Get(0).GetNumberAsDouble()), float(o->Get(1).GetNumberAsDouble())};
    if (s && s->ArrayLen() >= 2 && s->Get(0).IsNumber() && s->Get(1).IsNumber())
      scale = {float(s->Get(0).GetNumberAsDouble()), float(s->Get(1).GetNumberAsDouble())};
    const float r = number(&e, "rotation", 0.0f);
    glm::mat3 T(1.0f), R(1.0f), S(1.0f);
    T[2] = glm::vec3(offset, 1.0f);
    R[0] = glm::vec3(std::cos(r), -std::sin(r), 0.0f);
    R[1] = glm::vec3(std::sin(r), std::cos(r), 0.0f);
    S[0][0] = scale.x;
    S[1][1] = scale.y;
    const glm::mat3 m = T * R * S;
    for (int c = 0; c < 3; ++c)
      for (int r2 = 0; r2 < 3; ++r2)
        if (!std::isfinite(m[c][r2])) return glm::mat3(1.0f);
    return m;
  }

  std::optional<Texture> decode(int source, bool srgb) const {
    std::string why;
    const tinygltf::Image& image = model.images[size_t(source)];
    std::optional<Texture> t = gltf::decode_image(image, source, srgb, &why);
    if (!t) {
      // An image file that could not be read: say why (tinygltf's own warning says only
      // that it failed, and -q hides it). The URI resolves as tinygltf resolves it.
      const std::optional<std::filesystem::path> p = gltf::external_file(file, image.uri);
      std::string reason;
      if (image.bufferView < 0 && p && !readable_regular_file(p->string(), gltf::kMaxFileBytes, &reason))
        why = "image " + std::to_string(source) + ": " + p->string() + ": " + reason;
      texture_problem(why);
    }
    return t;
  }

  // ---- materials ------------------------------------------------------------------------
  void load_materials() {
    material_base = uint32_t(scene.materials.size());
    for (const tinygltf::Material& g : model.materials) {
      Material m;
      m.name = g.name;
      const auto& pbr = g.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() >= 3) m.base_color = vec3_of(pbr.baseColorFactor, m.base_color);
      else m.base_color = glm::vec3(1.0f);  // glTF default factor
      m.base_alpha = pbr.baseColorFactor.size() >= 4 ? float(pbr.baseColorFactor[3]) : 1.0f;
      m.base_color_texture = texture_ref(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                         pbr.baseColorTexture.extensions, true);
      m.metallic = float(pbr.metallicFactor);
      m.roughness = float(pbr.roughnessFactor);
      m.metallic_roughness_texture =
          texture_ref(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                      pbr.metallicRoughnessTexture.extensions, false);
      m.normal_texture = texture_ref(g.normalTexture.index, g.normalTexture.texCoord, g.normalTexture.extensions, false);
      m.normal_scale = float(g.normalTexture.scale);
      bool odd_alpha_mode = false;  // said once the material has its label
      if (g.alphaMode == "MASK") m.alpha_mode = AlphaMode::Mask;
      else if (g.alphaMode == "BLEND") m.alpha_mode = AlphaMode::Blend;
      else odd_alpha_mode = g.alphaMode != "OPAQUE" && !g.alphaMode.empty();
      m.alpha_cutoff = float(g.alphaCutoff);
      m.emissive = vec3_of(g.emissiveFactor, glm::vec3(0.0f));
      if (const auto* e = extension(g.extensions, "KHR_materials_emissive_strength"))
        m.emissive *= number(e, "emissiveStrength", 1.0f);
      m.emissive_texture = texture_ref(g.emissiveTexture.index, g.emissiveTexture.texCoord,
                                       g.emissiveTexture.extensions, true);
      if (const auto* e = extension(g.extensions, "KHR_materials_transmission")) {
        m.transmission = number(e, "transmissionFactor", 0.0f);
        m.transmission_texture = texture_ref(member(*e, "transmissionTexture"), false);
      }
      if (const auto* e = extension(g.extensions, "KHR_materials_ior")) m.ior = number(e, "ior", 1.5f);
      if (const auto* e = extension(g.extensions, "KHR_materials_volume")) {
        m.thickness = number(e, "thicknessFactor", 0.0f);
        m.attenuation_color = vec3_of(e, "attenuationColor", glm::vec3(1.0f));
        m.attenuation_distance =
            number(e, "attenuationDistance", std::numeric_limits<float>::infinity());
      }
      m.double_sided = g.doubleSided;
      if (!finite(m.base_color) || !finite(m.emissive) || !std::isfinite(m.metallic) ||
          !std::isfinite(m.roughness) || !std::isfinite(m.transmission) || !std::isfinite(m.base_alpha) ||
          !std::isfinite(m.alpha_cutoff) || !std::isfinite(m.normal_scale) || !std::isfinite(m.ior) ||
          !std::isfinite(m.thickness) || !finite(m.attenuation_color))  // (an infinite attenuationDistance is none)
        throw Error(file + ": material '" + g.name + "' has non-finite parameters");
      m.normal_scale = std::clamp(m.normal_scale, -kNormalScaleLimit, kNormalScaleLimit);
      scene.materials.push_back(std::move(m));
      const uint32_t index = uint32_t(scene.materials.size() - 1);
      if (odd_alpha_mode)
        warn(material_label(index) + ": alphaMode '" + g.alphaMode + "' is none of OPAQUE, MASK, BLEND; read as OPAQUE");
      warn_out_of_range(index);
    }
  }

  uint32_t material_index(int gltf_material) {
    if (gltf_material >= 0 && size_t(gltf_material) < model.materials.size())
      return material_base + uint32_t(gltf_material);
    if (gltf_material >= 0) warn("material " + std::to_string(gltf_material) + " out of range");
    if (default_material < 0) {
      Material m;
      m.name = "default";
      scene.materials.push_back(m);
      default_material = int(scene.materials.size() - 1);
    }
    return uint32_t(default_material);
  }

  // ---- meshes ---------------------------------------------------------------------------
  void load_mesh(int mesh_index, const glm::mat4& world) {
    const tinygltf::Mesh& mesh = model.meshes[size_t(mesh_index)];
    const std::string mesh_name =
        "mesh '" + (mesh.name.empty() ? std::to_string(mesh_index) : mesh.name) + "'";
    const std::string where = file + ": " + mesh_name;
    const glm::mat3 linear(world);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));  // n' = M^-T n
    const bool flip = glm::determinant(linear) < 0.0f;  // mirrored: keep CCW front faces

    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        warn(mesh_name + " primitive " + std::to_string(p) + ": mode " + std::to_string(mode) +
             (mode >= 0 && mode <= 3 ? " (points/lines) skipped" : " (no glTF mode: 0-6) skipped"));
        continue;
      }
      auto attr = [&](const char* name) {
        auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
      };
      if (attr("POSITION") < 0) {
        warn(mesh_name + " primitive " + std::to_string(p) + " has no POSITION, skipped");
        continue;
      }
      if (attr("COLOR_0") >= 0)
        warn_unsupported("COLOR_0", mesh_name + " has vertex colours (COLOR_0), which are not read: its base "
                                    "colour is the material's alone");
      if (!prim.targets.empty() && any_morph_weight(mesh.weights))
        warn_unsupported("morph", mesh_name + " has morph targets with non-zero weights, which are not applied: "
                                  "its base shape is rendered");
      gltf::check_attribute_type(model, attr("POSITION"), "POSITION", quantized, where + " POSITION");
      std::vector<float> pos = gltf::read_floats(model, attr("POSITION"), 3, where + " POSITION");
      const uint32_t material = material_index(prim.material);
      const bool normal_mapped = scene.materials[material].normal_texture.used();
      const size_t vertices = pos.size() / 3;
      // Optional per-vertex attribute with `components` floats: empty when absent.
      auto optional_attribute = [&](const char* name, int components) {
        std::vector<float> out;
        if (attr(name) < 0) return out;
        gltf::check_attribute_type(model, attr(name), name, quantized, where + " " + name);
        out = gltf::read_floats(model, attr(name), components, where + " " + name);
        for (float f : out)
          if (!std::isfinite(f)) throw Error(where + ": NaN/Inf in " + name);
        if (out.size() != vertices * size_t(components))
          throw Error(where + ": " + name + " count differs from POSITION");
        return out;
      };
      for (float f : pos)
        if (!std::isfinite(f)) throw Error(where + ": NaN/Inf in POSITION");
      const std::vector<float> nrm = optional_attribute("NORMAL", 3);
      const std::vector<float> uv = optional_attribute("TEXCOORD_0", 2);
      const std::vector<float> uv1 = uses_texcoord1 ? optional_attribute("TEXCOORD_1", 2) : std::vector<float>{};
      {
        // A texture read through a set the primitive lacks shows its texel at (0, 0) all over.
        const Material& m = scene.materials[material];
        for (const TextureRef* ref : m.texture_slots())
          if (ref->used() && (ref->texcoord == 1 ? uv1 : uv).empty()) {
            warn_unsupported(mesh_name + " TEXCOORD_" + std::to_string(ref->texcoord),
                             mesh_name + " primitive " + std::to_string(p) + ": " + material_label(material) + " reads TEXCOORD_" +
                                 std::to_string(ref->texcoord) +
                                 ", which the primitive lacks: each of its textures shows one texel all over");
            break;
          }
      }
      // Without NORMAL the file's tangents MUST be ignored (glTF 3.7.2.1): flat normals, and
      // tangents from the UV gradients.
      const std::vector<float> tangent =
          normal_mapped && !nrm.empty() ? optional_attribute("TANGENT", 4) : std::vector<float>{};

      std::vector<uint32_t> index;
      if (prim.indices >= 0) {
        index = gltf::read_indices(model, prim.indices, where + " indices");
        for (uint32_t i : index)
          if (i >= vertices) throw Error(where + ": index " + std::to_string(i) + " out of range");
      } else {
        index.resize(vertices);
        for (size_t i = 0; i < vertices; ++i) index[i] = uint32_t(i);
      }
      // Strips and fans to a triangle list, keeping the glTF winding (spec 3.7.2.1).
      std::vector<uint32_t> tri;
      if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (const size_t extra = index.size() % 3; extra != 0)
          warn(mesh_name + " primitive " + std::to_string(p) + ": " + std::to_string(index.size()) +
               (prim.indices >= 0 ? " indices" : " vertices") +
               " for TRIANGLES, not a multiple of 3: the last " + std::to_string(extra) + " ignored");
        tri.assign(index.begin(), index.begin() + (index.size() / 3) * 3);
      } else {
        for (size_t i = 2; i < index.size(); ++i) {
          if (mode == TINYGLTF_MODE_TRIANGLE_FAN) tri.insert(tri.end(), {index[0], index[i - 1], index[i]});
          else if (i % 2 == 0) tri.insert(tri.end(), {index[i - 2], index[i - 1], index[i]});
          else tri.insert(tri.end(), {index[i - 1], index[i - 2], index[i]});
        }
      }

      // Normal maps need a tangent frame: the file's, else one from the gradients of the
      // UV set the normal texture reads (glTF: its texCoord).
      const bool normal_uv1 = normal_mapped && scene.materials[material].normal_texture.texcoord == 1;
      const std::vector<float> tangents =
          !normal_mapped || !tangent.empty()
              ? tangent
              : uv_gradient_tangents(pos, nrm, normal_map_uvs(scene.materials[material].normal_texture, normal_uv1 ? uv1 : uv), tri);
      if (normal_mapped) scene.tangents.resize(scene.positions.size(), glm::vec4(0.0f));
      if (uses_texcoord1) scene.uvs1.resize(scene.positions.size(), glm::vec2(0.0f));
      size_t rewound = 0;
      for (size_t t = 0; t + 2 < tri.size(); t += 3) {
        uint32_t v[3] = {tri[t], tri[t + 1], tri[t + 2]};
        if (flip) std::swap(v[1], v[2]);
        glm::vec3 w[3];
        for (int k = 0; k < 3; ++k) {
          const float* q = &pos[size_t(v[k]) * 3];
          w[k] = glm::vec3(world * glm::vec4(q[0], q[1], q[2], 1.0f));
        }
        if (!finite(w[0]) || !finite(w[1]) || !finite(w[2])) {
          ++scene.dropped_degenerate;
          continue;
        }
        const glm::vec3 extent = glm::max(glm::max(glm::abs(w[0]), glm::abs(w[1])), glm::abs(w[2]));
        if (std::max(extent.x, std::max(extent.y, extent.z)) > kMaxCoordinate) {
          ++scene.dropped_degenerate, ++dropped_far;
          continue;
        }
        const glm::vec3 e1 = w[1] - w[0], e2 = w[2] - w[0];
        const glm::vec3 c = glm::cross(e1, e2);
        const float area2 = glm::dot(c, c), least = 1e-14f * glm::dot(e1, e1) * glm::dot(e2, e2);
        glm::vec3 flat;
        if (area2 <= std::numeric_limits<float>::max() && least <= std::numeric_limits<float>::max()) {
          // Zero area, also relative to the edge lengths (collinear up to float rounding).
          if (!(area2 > least)) {
            ++scene.dropped_degenerate;
            if (area2 == 0.0f) {  // an area too small for float's squares, or none at all
              const glm::dvec3 dc = glm::cross(glm::dvec3(e1), glm::dvec3(e2));
              if (glm::dot(dc, dc) > 0.0) ++dropped_tiny;
            }
            continue;
          }
          flat = c / std::sqrt(area2);
        } else {
          // Edges of 1e10 units and more (a planet in metres): their squares overflow float;
          // the same test in double.
          const glm::dvec3 d1(e1), d2(e2), dc = glm::cross(d1, d2);
          const double darea2 = glm::dot(dc, dc);
          if (!(darea2 > 1e-14 * glm::dot(d1, d1) * glm::dot(d2, d2))) {
            ++scene.dropped_degenerate;
            continue;
          }
          flat = glm::vec3(dc / std::sqrt(darea2));
        }
        glm::vec3 n[3] = {flat, flat, flat};
        if (!nrm.empty()) {
          for (int k = 0; k < 3; ++k) {
            const float* q = &nrm[size_t(v[k]) * 3];
            glm::vec3 tn = normal_matrix * glm::vec3(q[0], q[1], q[2]);
            float len = glm::length(tn);
            if (len > 1e-20f && std::isfinite(len)) n[k] = tn / len;
            else if (const std::optional<glm::vec3> u = unit_direction(tn)) n[k] = *u;  // |tn|^2 over- or underflowed
          }
          // Wound against its vertex normals: the renderer takes the winding's side as the
          // front (shading normals turned to it, volumes entered through it), so such a mesh
          // rendered flat-shaded and its glass refracted the wrong way. Like pbrt-v4, which
          // turns the geometric normal to the shading normal, the normals decide: swap the
          // winding. Per triangle, constant over it, and only where all three normals point
          // away: a triangle on a sharp crease smoothed across keeps its winding.
          if (glm::dot(n[0], flat) < 0.0f && glm::dot(n[1], flat) < 0.0f && glm::dot(n[2], flat) < 0.0f) {
            std::swap(v[1], v[2]);
            std::swap(w[1], w[2]);
            std::swap(n[1], n[2]);
            ++rewound;
          }
        }
        for (int k = 0; k < 3; ++k) {
          scene.positions.push_back(w[k]);
          scene.normals.push_back(n[k]);
          auto uv_at = [&](const std::vector<float>& set) {
            return set.empty() ? glm::vec2(0.0f) : glm::vec2(set[size_t(v[k]) * 2], set[size_t(v[k]) * 2 + 1]);
          };
          scene.uvs.push_back(uv_at(uv));
          if (uses_texcoord1) scene.uvs1.push_back(uv_at(uv1));
          if (normal_mapped) {
            const float* q = tangents.empty() ? nullptr : &tangents[size_t(v[k]) * 4];
            glm::vec3 tw = q ? linear * glm::vec3(q[0], q[1], q[2]) : glm::vec3(0.0f);
            tw -= n[k] * glm::dot(n[k], tw);  // orthogonal to the (transformed) shading normal
            const float len = glm::length(tw);
            // A mirroring transform flips the bitangent relative to cross(N, T).
            const float sign = (q && q[3] < 0.0f ? -1.0f : 1.0f) * (flip ? -1.0f : 1.0f);
            scene.tangents.push_back(len > 1e-20f && std::isfinite(len) ? glm::vec4(tw / len, sign) : glm::vec4(0.0f));
          } else if (!scene.tangents.empty()) {
            scene.tangents.push_back(glm::vec4(0.0f));
          }
        }
        scene.material_of.push_back(material);
      }
      if (rewound > 0)
        warn(mesh_name + " primitive " + std::to_string(p) + ": " + std::to_string(rewound) + " of " +
             std::to_string(tri.size() / 3) + " triangles wound against their normals; their normals' side is the front");
    }
  }

  // ---- nodes ------------------------------------------------------------------------------
  // glTF 2.0 §5.25: a node's matrix must be an affine TRS, its last row 0 0 0 1. (With a
  // matrix, tinygltf 2.7 drops the node's translation, rotation and scale unread.)
  void warn_about_matrix(int node_index) const {
    const tinygltf::Node& n = model.nodes[size_t(node_index)];
    if (n.matrix.size() != 16) return;
    if (n.matrix[3] != 0.0 || n.matrix[7] != 0.0 || n.matrix[11] != 0.0 || n.matrix[15] != 1.0)
      warn("node " + std::to_string(node_index) + (n.name.empty() ? "" : " '" + n.name + "'") +
           "'s matrix is not affine (its last row is not 0 0 0 1); that row is ignored");
  }

  static glm::mat4 local_matrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
      glm::mat4 m;
      for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = float(n.matrix[size_t(i)]);  // column-major
      return m;
    }
    glm::mat4 t(1.0f), r(1.0f), s(1.0f);
    if (n.translation.size() == 3) t = glm::translate(glm::mat4(1.0f), vec3_of(n.translation, glm::vec3(0.0f)));
    if (n.rotation.size() == 4) {
      glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));
      float len = glm::length(q);
      if (len > 0.0f && std::isfinite(len)) r = glm::mat4_cast(q / len);
    }
    if (n.scale.size() == 3) s = glm::scale(glm::mat4(1.0f), vec3_of(n.scale, glm::vec3(1.0f)));
    return t * r * s;  // glTF: M = T * R * S
  }

  // glTF 3.5.3: the node hierarchy MUST be a set of disjoint strict trees. A node reached
  // twice (a second parent, a root that is also a child, a cycle) is an error: instancing
  // through shared nodes grew a 17 kB file to millions of triangles. The walk keeps its
  // own stack, so a valid chain of any depth loads.
  std::vector<bool> visited;

  size_t dropped_far = 0;   // triangles beyond kMaxCoordinate
  size_t dropped_tiny = 0;  // triangles too small for float (their area's square underflows)

  void visit(int root, const glm::mat4& parent) {
    visited.resize(model.nodes.size(), false);
    std::vector<std::pair<int, glm::mat4>> stack = {{root, parent}};
    while (!stack.empty()) {
      const auto [node_index, above] = stack.back();
      stack.pop_back();
      if (node_index < 0 || size_t(node_index) >= model.nodes.size())
        throw Error(file + ": node " + std::to_string(node_index) + " out of range");
      if (visited[size_t(node_index)])
        throw Error(file + ": node " + std::to_string(node_index) +
                    (model.nodes[size_t(node_index)].name.empty() ? "" : " '" + model.nodes[size_t(node_index)].name + "'") +
                    " is reached twice (cyclic, or a second parent); glTF nodes form disjoint trees");
      visited[size_t(node_index)] = true;
      const glm::mat4 world = visit_node(node_index, above);
      const std::vector<int>& children = model.nodes[size_t(node_index)].children;
      for (auto c = children.rbegin(); c != children.rend(); ++c) stack.emplace_back(*c, world);  // in order, depth first
    }
  }

  // One node's own content at its world transform, which it returns for its children.
  glm::mat4 visit_node(int node_index, const glm::mat4& parent) {
    const tinygltf::Node& node = model.nodes[size_t(node_index)];
    warn_about_matrix(node_index);
    const glm::mat4 world = parent * (animation.animates(node_index)
                                          ? animation.pose(node_index, gltf::rest_pose(node), float(options.time.value_or(0.0))).matrix()
                                          : local_matrix(node));
    for (int i = 0; i < 16; ++i)
      if (!std::isfinite(glm::value_ptr(world)[i]))
        throw Error(file + ": node '" + node.name + "' has a non-finite transform");
    if (node.skin >= 0)
      warn_unsupported("skin", "node '" + node.name + "' is skinned; skins are not applied: its mesh is drawn in "
                               "its bind pose under the node's transform");
    if (any_morph_weight(node.weights))
      warn_unsupported("morph", "node '" + node.name + "' sets morph weights, which are not applied: its mesh's base "
                                "shape is rendered");
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= model.meshes.size())
        throw Error(file + ": node '" + node.name + "' mesh " + std::to_string(node.mesh) + " out of range");
      load_mesh(node.mesh, world);
    }
    if (node.camera >= 0) add_camera(node, world);
    if (const auto* e = extension(node.extensions, "KHR_lights_punctual")) {
      const tinygltf::Value* l = member(*e, "light");
      if (l && l->IsNumber()) add_light(l->GetNumberAsInt(), node, world);
    }
    return world;
  }

  // A camera the scene cannot use is left out; those after it (--camera N, a rig's
  // default_camera index) move up one index, which the warning says.
  void ignore_camera(const std::string& name, const std::string& why) const {
    warn("camera '" + name + "' " + why + ", ignored (the cameras after it move up one index)");
  }

  void add_camera(const tinygltf::Node& node, const glm::mat4& world) {
    if (size_t(node.camera) >= model.cameras.size()) {
      warn("node '" + node.name + "' camera out of range, ignored");
      return;
    }
    const tinygltf::Camera& g = model.cameras[size_t(node.camera)];
    const bool orthographic = g.type == "orthographic";
    if (g.type != "perspective" && !orthographic) {
      ignore_camera(g.name, "has unknown type '" + g.type + "'");
      return;
    }
    // glTF cameras look down -Z with +Y up in their node's frame.
    const glm::mat3 m(world);
    Camera c;
    c.name = g.name.empty() ? node.name : g.name;
    c.position = glm::vec3(world[3]);
    glm::vec3 f = m * glm::vec3(0.0f, 0.0f, -1.0f), u = m * glm::vec3(0.0f, 1.0f, 0.0f);
    glm::vec3 r = glm::cross(f, u);
    if (!(glm::length(f) > 0.0f) || !(glm::length(r) > 0.0f)) {
      ignore_camera(c.name, "has a degenerate transform");
      return;
    }
    c.forward = glm::normalize(f);
    const bool orthonormal_view = is_rotation_times_scale(m);
    if (orthonormal_view) {
      c.right = glm::normalize(glm::cross(c.forward, u));
      c.up = glm::cross(c.right, c.forward);
    } else {
      // The view is the node's inverse (glTF 2.0 §3.10.1): a local ray (a, b, -1) goes to
      // m (a, b, -1) in the world, so a mirrored node mirrors the image and a node scaled
      // in x alone widens what a pixel sees. Relative to the forward axis's length.
      const float length = glm::length(f);
      c.right = m * glm::vec3(1.0f, 0.0f, 0.0f) / length;
      c.up = u / length;
    }
    if (!finite(c.position) || !finite(c.forward) || !finite(c.right) || !finite(c.up)) {
      ignore_camera(c.name, "has a non-finite transform");
      return;
    }
    // The view's size: a field of view, or an orthographic camera's half extents in the
    // node's units (the node's scale scales them, as it does the clipping planes below).
    double znear = 0.0, zfar = 0.0;
    if (orthographic) {
      const auto& o = g.orthographic;
      const double ymag = double(o.ymag) * double(glm::length(f));
      if (!(o.ymag > 0.0 && std::isfinite(ymag) && float(ymag) > 0.0f && std::isfinite(float(ymag)))) {
        ignore_camera(c.name, "has ymag " + std::to_string(o.ymag) + " (orthographic: not > 0)");
        return;
      }
      if (!(o.xmag > 0.0 && std::isfinite(o.xmag))) {
        ignore_camera(c.name, "has xmag " + std::to_string(o.xmag) + " (orthographic: not > 0)");
        return;
      }
      c.ymag = float(ymag);
      c.aspect = float(o.xmag / o.ymag);
      if (!(c.aspect > 0.0f && std::isfinite(c.aspect))) c.aspect = 0.0f;  // out of float's range: unknown
      znear = o.znear;
      zfar = o.zfar;
    } else {
      const auto& p = g.perspective;
      if (!valid_yfov_degrees(glm::degrees(p.yfov))) {
        char why[128];
        std::snprintf(why, sizeof why, "has yfov %g rad (%g degrees), outside (%g, %g) degrees", p.yfov,
                      glm::degrees(p.yfov), double(kMinYfovDegrees), double(kMaxYfovDegrees));
        ignore_camera(c.name, why);
        return;
      }
      if (!(p.aspectRatio >= 0.0 && std::isfinite(p.aspectRatio))) {  // 0: not given
        ignore_camera(c.name, "has aspectRatio " + std::to_string(p.aspectRatio) + " (not > 0)");
        return;
      }
      c.yfov = float(p.yfov);
      c.aspect = float(p.aspectRatio);
      znear = p.znear;
      zfar = p.zfar;
    }
    // The planes are depths in the camera node's frame: -(m^-1 (q - position)).z = n.(q -
    // position) with n = m^-T (0, 0, -1), so in the world they are planes of normal n / |n|
    // at depth z / |n|. For a rotation times a uniform scale s, n is forward / s.
    float unit = glm::length(f);
    if (!orthonormal_view) {
      const glm::vec3 n = glm::transpose(glm::inverse(m)) * glm::vec3(0.0f, 0.0f, -1.0f);
      unit = 1.0f / glm::length(n);
      c.clip_axis = n * unit;
      if (!finite(c.clip_axis) || !std::isfinite(unit)) {
        ignore_camera(c.name, "has a non-finite transform");
        return;
      }
    }
    // glTF: znear > 0 (perspective) or >= 0 (orthographic), zfar > znear; 0 is read as no
    // plane. A plane that breaks the rule is left out with a warning, the camera kept (so
    // the cameras after it keep their indices): a negative znear used to set a far plane at
    // 0, clipping the whole view (black), and a zfar <= znear was dropped without a word.
    char why[160];
    if (!(znear >= 0.0 && std::isfinite(znear))) {
      std::snprintf(why, sizeof why, "has znear %g (not >= 0): no near plane", znear);
      warn("camera '" + c.name + "' " + why);
      znear = 0.0;
    }
    if (zfar != 0.0 && !(zfar > znear)) {
      std::snprintf(why, sizeof why, "has zfar %g (not greater than znear %g): no far plane", zfar, znear);
      warn("camera '" + c.name + "' " + why);
      zfar = 0.0;
    }
    if (znear > 0.0) c.znear = float(znear) * unit;
    if (zfar > 0.0 && std::isfinite(zfar)) c.zfar = float(zfar) * unit;  // none given: infinite
    scene.cameras.push_back(c);
  }

  void add_light(int index, const tinygltf::Node& node, const glm::mat4& world) {
    if (index < 0 || size_t(index) >= model.lights.size()) {
      warn("node '" + node.name + "' light out of range, ignored");
      return;
    }
    const tinygltf::Light& g = model.lights[size_t(index)];
    Light l;
    l.name = g.name.empty() ? node.name : g.name;
    if (g.type == "point") l.type = Light::Type::Point;
    else if (g.type == "spot") l.type = Light::Type::Spot;
    else if (g.type == "directional") l.type = Light::Type::Directional;
    else {
      warn("light '" + l.name + "' has unknown type '" + g.type + "', ignored");
      return;
    }
    l.position = glm::vec3(world[3]);
    if (l.type != Light::Type::Point) {
      // Lights point down the node's -Z, whatever its scale (KHR_lights_punctual).
      const std::optional<glm::vec3> d = unit_direction(glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f));
      if (!d) {
        warn("light '" + l.name + "' has a degenerate transform (no direction), ignored");
        return;
      }
      l.direction = *d;
    }
    l.intensity = vec3_of(g.color, glm::vec3(1.0f)) * float(g.intensity);
    l.range = float(g.range);  // 0 when absent (tinygltf): no range; a negative one is refused below
    if (l.type == Light::Type::Spot) {
      l.inner_cone = float(g.spot.innerConeAngle);
      l.outer_cone = float(g.spot.outerConeAngle);
      if (const std::string cone = spot_cone_warning(l); !cone.empty()) warn(cone);
    }
    if (!finite(l.intensity) || !finite(l.position)) throw Error(file + ": light '" + l.name + "' is not finite");
    if (const std::string problem = light_problem(l); !problem.empty())
      throw Error(file + ": light '" + l.name + "': " + problem);
    scene.lights.push_back(l);
  }

  void load_nodes(const glm::mat4& transform) {
    int s = model.defaultScene;
    if (s < 0 && !model.scenes.empty()) s = 0;
    if (s >= int(model.scenes.size())) throw Error(file + ": default scene " + std::to_string(s) + " out of range");
    if (s >= 0) {
      for (int n : model.scenes[size_t(s)].nodes) visit(n, transform);
      return;
    }
    // No scene: render every root node (lenient; the spec leaves this to the application).
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const auto& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < is_child.size()) is_child[size_t(c)] = true;
    for (size_t n = 0; n < model.nodes.size(); ++n)
      if (!is_child[n]) visit(int(n), transform);
  }
};

}  // namespace

void load_gltf_into(Scene& scene, const std::filesystem::path& path, const glm::mat4& transform,
                    const LoadOptions& options) {
  const std::string file = path.string();
  tinygltf::Model model;
  std::string warning;
  gltf::read_gltf_model(path, model, &warning);
  if (!warning.empty() && !options.quiet) {
    std::replace(warning.begin(), warning.end(), '\n', ' ');
    std::fprintf(stderr, "warning: %s: %s\n", file.c_str(), warning.c_str());
  }
  for (const std::string& e : model.extensionsRequired)
    if (std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), e) == kSupportedExtensions.end())
      throw Error(file + ": requires the glTF extension " + e + ", which zigzag does not support");
  const bool quantized = std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(),
                                   "KHR_mesh_quantization") != model.extensionsUsed.end();
  scene.source_files.push_back(file);
  auto external = [&](const std::string& uri) {
    if (const std::optional<std::filesystem::path> f = gltf::external_file(path, uri)) scene.source_files.push_back(f->string());
  };
  for (const tinygltf::Buffer& b : model.buffers) external(b.uri);
  for (const tinygltf::Image& i : model.images) external(i.uri);
  Loader loader{model, scene, options, file, 0, -1, {}, false, quantized, {}, {}, {}};
  loader.load_materials();
  loader.animation = gltf::read_animations(model, file, [&](const std::string& m) { loader.warn(m); });
  scene.animated = scene.animated || !loader.animation.empty();
  scene.animation_end = std::max(scene.animation_end, loader.animation.end_time());
  const size_t dropped_before = scene.dropped_degenerate;
  loader.load_nodes(transform);
  if (loader.dropped_far > 0)
    loader.warn(std::to_string(loader.dropped_far) + " triangle(s) dropped: a vertex lies beyond +-1e18 units once placed, "
                "farther than float ray intersection holds (scale the scene down)");
  if (loader.dropped_tiny > 0)
    loader.warn(std::to_string(loader.dropped_tiny) + " triangle(s) dropped: edges below about 1e-10 units, smaller "
                "than float ray intersection holds (scale the scene up)");
  if (const size_t dropped = scene.dropped_degenerate - dropped_before - loader.dropped_far - loader.dropped_tiny; dropped > 0)
    loader.warn(std::to_string(dropped) + " degenerate triangle(s) dropped (zero area, or vertices not finite once placed)");
}

}  // namespace zz
