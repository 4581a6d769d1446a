// glTF 2.0 -> Scene: flattens the default scene's node hierarchy into world-space
// triangles, and reads materials, textures, KHR_lights_punctual lights and cameras.
#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "core/error.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_image.h"
#include "scene/loader.h"

namespace zz {
namespace {

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

struct Loader {
  const tinygltf::Model& model;
  Scene& scene;
  const LoadOptions& options;
  std::string file;  // for messages
  uint32_t material_base = 0;
  int default_material = -1;
  std::map<std::pair<int, bool>, int> texture_of_image;  // (image, srgb) -> scene texture
  Animation animation;  // sampled at options.time for every animated node

  void warn(const std::string& msg) const {
    if (!options.quiet) std::fprintf(stderr, "warning: %s: %s\n", file.c_str(), msg.c_str());
  }

  // Scene texture for glTF texture `index`, decoded once per colour space; -1 if unusable.
  int texture(int index, bool srgb) {
    if (index < 0 || size_t(index) >= model.textures.size()) {
      if (index >= 0) warn("texture " + std::to_string(index) + " out of range, ignored");
      return -1;
    }
    const int source = model.textures[size_t(index)].source;
    if (source < 0 || size_t(source) >= model.images.size()) {
      warn("texture " + std::to_string(index) + " has no usable image source, ignored");
      return -1;
    }
    auto key = std::make_pair(source, srgb);
    if (auto it = texture_of_image.find(key); it != texture_of_image.end()) return it->second;
    int result = -1;
    if (std::optional<Texture> t = decode(source, srgb)) {
      scene.textures.push_back(std::move(*t));
      result = int(scene.textures.size() - 1);
    }
    texture_of_image[key] = result;
    return result;
  }

  // Mean of each channel of a linear texture (glTF texture `index`), or nullopt.
  std::optional<glm::vec4> texture_mean(int index) {
    if (index < 0 || size_t(index) >= model.textures.size()) return std::nullopt;
    const int source = model.textures[size_t(index)].source;
    if (source < 0 || size_t(source) >= model.images.size()) return std::nullopt;
    std::optional<Texture> t = decode(source, false);
    if (!t) return std::nullopt;
    glm::dvec4 sum(0.0);
    for (const glm::vec4& c : t->texels) sum += glm::dvec4(c);
    return glm::vec4(sum / double(t->texels.size()));
  }

  std::optional<Texture> decode(int source, bool srgb) const {
    std::string why;
    std::optional<Texture> t = gltf::decode_image(model.images[size_t(source)], source, srgb, &why);
    if (!t) warn(why);
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
      m.base_color_texture = texture(pbr.baseColorTexture.index, true);
      // Metallic/roughness textures are not sampled per hit: the Whitted model takes one
      // mirror and one highlight coefficient per material. The factors are scaled by the
      // texture's mean (B = metallic, G = roughness) so that a textured material with the
      // default factors 1 is not mistaken for a rough pure metal (black diffuse).
      m.metallic = float(pbr.metallicFactor);
      m.roughness = float(pbr.roughnessFactor);
      if (auto mean = texture_mean(pbr.metallicRoughnessTexture.index)) {
        m.metallic *= mean->b;
        m.roughness *= mean->g;
      }
      m.emissive = vec3_of(g.emissiveFactor, glm::vec3(0.0f));
      if (const auto* e = extension(g.extensions, "KHR_materials_emissive_strength"))
        m.emissive *= number(e, "emissiveStrength", 1.0f);
      m.emissive_texture = texture(g.emissiveTexture.index, true);
      if (const auto* e = extension(g.extensions, "KHR_materials_transmission"))
      {
        // transmissionTexture (R channel) enters by its mean, like metallic/roughness.
        m.transmission = number(e, "transmissionFactor", 0.0f);
        const tinygltf::Value* t = member(*e, "transmissionTexture");
        const tinygltf::Value* ti = t ? member(*t, "index") : nullptr;
        if (ti && ti->IsNumber())
          if (auto mean = texture_mean(ti->GetNumberAsInt())) m.transmission *= mean->r;
      }
      if (const auto* e = extension(g.extensions, "KHR_materials_ior")) m.ior = number(e, "ior", 1.5f);
      if (const auto* e = extension(g.extensions, "KHR_materials_volume")) {
        m.attenuation_color = vec3_of(e, "attenuationColor", glm::vec3(1.0f));
        m.attenuation_distance =
            number(e, "attenuationDistance", std::numeric_limits<float>::infinity());
      }
      m.double_sided = g.doubleSided;
      if (!finite(m.base_color) || !finite(m.emissive) || !std::isfinite(m.metallic) ||
          !std::isfinite(m.roughness) || !std::isfinite(m.transmission))
        throw Error(file + ": material '" + g.name + "' has non-finite parameters");
      scene.materials.push_back(std::move(m));
    }
  }

  // KHR_texture_transform on the base colour texture, baked into the triangle UVs
  // (one transform per material; the emissive texture shares it).
  glm::mat3 uv_transform(int material) const {
    glm::mat3 t(1.0f);
    if (material < 0 || size_t(material) >= model.materials.size()) return t;
    const auto& info = model.materials[size_t(material)].pbrMetallicRoughness.baseColorTexture;
    const auto* e = extension(info.extensions, "KHR_texture_transform");
    if (!e) return t;
    const tinygltf::Value* o = member(*e, "offset");
    const tinygltf::Value* s = member(*e, "scale");
    glm::vec2 offset(0.0f), scale(1.0f);
    if (o && o->ArrayLen() >= 2 && o->Get(0).IsNumber() && o->Get(1).IsNumber())
      offset = {float(o->Get(0).GetNumberAsDouble()), float(o->Get(1).GetNumberAsDouble())};
    if (s && s->ArrayLen() >= 2 && s->Get(0).IsNumber() && s->Get(1).IsNumber())
      scale = {float(s->Get(0).GetNumberAsDouble()), float(s->Get(1).GetNumberAsDouble())};
    const float r = number(e, "rotation", 0.0f);
    // Extension spec: uv' = T * R * S * uv with R = [[cos, sin], [-sin, cos]].
    glm::mat3 T(1.0f), R(1.0f), S(1.0f);
    T[2] = glm::vec3(offset, 1.0f);
    R[0] = glm::vec3(std::cos(r), -std::sin(r), 0.0f);
    R[1] = glm::vec3(std::sin(r), std::cos(r), 0.0f);
    S[0][0] = scale.x;
    S[1][1] = scale.y;
    return T * R * S;
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
             " (points/lines) skipped");
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
      std::vector<float> pos = gltf::read_floats(model, attr("POSITION"), 3, where + " POSITION");
      std::vector<float> nrm, uv;
      if (attr("NORMAL") >= 0) nrm = gltf::read_floats(model, attr("NORMAL"), 3, where + " NORMAL");
      if (attr("TEXCOORD_0") >= 0) uv = gltf::read_floats(model, attr("TEXCOORD_0"), 2, where + " TEXCOORD_0");
      const size_t vertices = pos.size() / 3;
      for (float f : pos)
        if (!std::isfinite(f)) throw Error(where + ": NaN/Inf in POSITION");
      for (float f : nrm)
        if (!std::isfinite(f)) throw Error(where + ": NaN/Inf in NORMAL");
      for (float f : uv)
        if (!std::isfinite(f)) throw Error(where + ": NaN/Inf in TEXCOORD_0");
      if (!nrm.empty() && nrm.size() != pos.size()) throw Error(where + ": NORMAL count differs from POSITION");
      if (!uv.empty() && uv.size() / 2 != vertices) throw Error(where + ": TEXCOORD_0 count differs from POSITION");

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
        tri.assign(index.begin(), index.begin() + (index.size() / 3) * 3);
      } else {
        for (size_t i = 2; i < index.size(); ++i) {
          if (mode == TINYGLTF_MODE_TRIANGLE_FAN) tri.insert(tri.end(), {index[0], index[i - 1], index[i]});
          else if (i % 2 == 0) tri.insert(tri.end(), {index[i - 2], index[i - 1], index[i]});
          else tri.insert(tri.end(), {index[i - 1], index[i - 2], index[i]});
        }
      }

      const uint32_t material = material_index(prim.material);
      const glm::mat3 uvt = uv_transform(prim.material);
      for (size_t t = 0; t + 2 < tri.size(); t += 3) {
        uint32_t v[3] = {tri[t], tri[t + 1], tri[t + 2]};
        if (flip) std::swap(v[1], v[2]);
        glm::vec3 w[3];
        for (int k = 0; k < 3; ++k) {
          const float* q = &pos[size_t(v[k]) * 3];
          w[k] = glm::vec3(world * glm::vec4(q[0], q[1], q[2], 1.0f));
        }
        const glm::vec3 e1 = w[1] - w[0], e2 = w[2] - w[0];
        const glm::vec3 c = glm::cross(e1, e2);
        const float area2 = glm::dot(c, c);
        // Zero area, also relative to the edge lengths (collinear up to float rounding).
        if (!(area2 > 1e-14f * glm::dot(e1, e1) * glm::dot(e2, e2)) || !finite(w[0]) ||
            !finite(w[1]) || !finite(w[2])) {
          ++scene.dropped_degenerate;
          continue;
        }
        const glm::vec3 flat = c / std::sqrt(area2);
        for (int k = 0; k < 3; ++k) {
          scene.positions.push_back(w[k]);
          glm::vec3 n = flat;
          if (!nrm.empty()) {
            const float* q = &nrm[size_t(v[k]) * 3];
            glm::vec3 tn = normal_matrix * glm::vec3(q[0], q[1], q[2]);
            float len = glm::length(tn);
            if (len > 1e-20f && std::isfinite(len)) n = tn / len;
          }
          scene.normals.push_back(n);
          glm::vec2 t2(0.0f);
          if (!uv.empty()) t2 = glm::vec2(uvt * glm::vec3(uv[size_t(v[k]) * 2], uv[size_t(v[k]) * 2 + 1], 1.0f));
          scene.uvs.push_back(t2);
        }
        scene.material_of.push_back(material);
      }
    }
  }

  // ---- nodes ------------------------------------------------------------------------------
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

  static constexpr size_t kMaxNodeInstances = size_t(1) << 20;
  size_t node_instances = 0;

  void visit(int node_index, const glm::mat4& parent, int depth) {
    if (node_index < 0 || size_t(node_index) >= model.nodes.size())
      throw Error(file + ": node " + std::to_string(node_index) + " out of range");
    if (depth > 256) throw Error(file + ": node hierarchy too deep or cyclic");
    // A DAG may instance a node exponentially often (each level referencing the next
    // twice): bound the instances, not only the depth.
    if (++node_instances > kMaxNodeInstances)
      throw Error(file + ": node hierarchy instances more than " + std::to_string(kMaxNodeInstances) +
                  " nodes (exponential instancing)");
    const tinygltf::Node& node = model.nodes[size_t(node_index)];
    const glm::mat4 world = parent * (animation.animates(node_index)
                                          ? animation.pose(node_index, gltf::rest_pose(node), float(options.time.value_or(0.0))).matrix()
                                          : local_matrix(node));
    for (int i = 0; i < 16; ++i)
      if (!std::isfinite(glm::value_ptr(world)[i]))
        throw Error(file + ": node '" + node.name + "' has a non-finite transform");
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
    for (int child : node.children) visit(child, world, depth + 1);
  }

  void add_camera(const tinygltf::Node& node, const glm::mat4& world) {
    if (size_t(node.camera) >= model.cameras.size()) {
      warn("node '" + node.name + "' camera out of range, ignored");
      return;
    }
    const tinygltf::Camera& g = model.cameras[size_t(node.camera)];
    if (g.type != "perspective") {
      warn("camera '" + g.name + "' is " + g.type + ", only perspective cameras are used");
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
      warn("camera '" + c.name + "' has a degenerate transform, ignored");
      return;
    }
    c.forward = glm::normalize(f);
    c.right = glm::normalize(glm::cross(c.forward, u));
    c.up = glm::cross(c.right, c.forward);
    if (!finite(c.position) || !finite(c.forward) || !finite(c.right) || !finite(c.up)) {
      warn("camera '" + c.name + "' has a non-finite transform, ignored");
      return;
    }
    const auto& p = g.perspective;
    c.yfov = p.yfov > 0.0 && p.yfov < 3.1 ? float(p.yfov) : 0.8f;
    c.aspect = p.aspectRatio > 0.0 ? float(p.aspectRatio) : 0.0f;
    if (p.znear > 0.0) c.znear = float(p.znear);
    c.zfar = p.zfar > p.znear ? float(p.zfar) : c.znear * 1e6f;  // 0 = infinite projection
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
    glm::vec3 d = glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f);  // lights point down -Z
    if (glm::length(d) > 0.0f) l.direction = glm::normalize(d);
    l.intensity = vec3_of(g.color, glm::vec3(1.0f)) * float(g.intensity);
    l.range = g.range > 0.0 ? float(g.range) : 0.0f;
    if (l.type == Light::Type::Spot) {
      l.inner_cone = float(g.spot.innerConeAngle);
      l.outer_cone = float(g.spot.outerConeAngle);
    }
    if (!finite(l.intensity) || !finite(l.position)) throw Error(file + ": light '" + l.name + "' is not finite");
    scene.lights.push_back(l);
  }

  void load_nodes(const glm::mat4& transform) {
    int s = model.defaultScene;
    if (s < 0 && !model.scenes.empty()) s = 0;
    if (s >= int(model.scenes.size())) throw Error(file + ": default scene " + std::to_string(s) + " out of range");
    if (s >= 0) {
      for (int n : model.scenes[size_t(s)].nodes) visit(n, transform, 0);
      return;
    }
    // No scene: render every root node (lenient; the spec leaves this to the application).
    std::vector<bool> is_child(model.nodes.size(), false);
    for (const auto& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < is_child.size()) is_child[size_t(c)] = true;
    for (size_t n = 0; n < model.nodes.size(); ++n)
      if (!is_child[n]) visit(int(n), transform, 0);
  }
};

}  // namespace

void load_gltf_into(Scene& scene, const std::filesystem::path& path, const glm::mat4& transform,
                    const LoadOptions& options) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(file + ": file not found");
  tinygltf::Model model;
  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(gltf::keep_encoded, nullptr);
  std::string err, warning;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  bool ok = false;
  try {
    ok = ext == ".glb" ? gltf.LoadBinaryFromFile(&model, &err, &warning, file)
                       : gltf.LoadASCIIFromFile(&model, &err, &warning, file);
  } catch (const std::exception& e) {  // tinygltf's JSON parser or an allocation
    throw Error(file + ": cannot parse glTF (" + e.what() + ")");
  }
  if (!ok) {
    std::string msg = err.empty() ? "cannot parse glTF" : err;
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    throw Error(file + ": " + msg);
  }
  if (!warning.empty() && !options.quiet) {
    std::replace(warning.begin(), warning.end(), '\n', ' ');
    std::fprintf(stderr, "warning: %s: %s\n", file.c_str(), warning.c_str());
  }
  Loader loader{model, scene, options, file, 0, -1, {}, {}};
  loader.load_materials();
  loader.animation = gltf::read_animations(model, file, [&](const std::string& m) { loader.warn(m); });
  scene.animated = scene.animated || !loader.animation.empty();
  scene.animation_end = std::max(scene.animation_end, loader.animation.end_time());
  loader.load_nodes(transform);
}

}  // namespace zz
