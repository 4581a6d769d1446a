// Builds tiny glTF files for the loader tests (JSON + external .bin, or a .glb), and a
// per-test temporary directory.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace zz::test {

inline std::filesystem::path temp_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("zz_scene_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& p, const std::string& s) {
  std::ofstream(p, std::ios::binary) << s;
}

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct GltfBuilder {
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}},
                        {"scene", 0},
                        {"scenes", {{{"nodes", nlohmann::json::array()}}}},
                        {"nodes", nlohmann::json::array()},
                        {"meshes", nlohmann::json::array()},
                        {"accessors", nlohmann::json::array()},
                        {"bufferViews", nlohmann::json::array()}};
  std::vector<uint8_t> bin;

  int view(const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + bytes);
    std::memcpy(bin.data() + offset, data, bytes);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    return int(doc["bufferViews"].size() - 1);
  }
  // components: 1 -> SCALAR, 2 -> VEC2, 3 -> VEC3.
  int floats(const std::vector<float>& v, int components) {
    int bv = view(v.data(), v.size() * sizeof(float));
    doc["accessors"].push_back({{"bufferView", bv}, {"componentType", 5126},
                                {"count", v.size() / size_t(components)},
                                {"type", components == 1 ? "SCALAR" : components == 2 ? "VEC2" : "VEC3"}});
    return int(doc["accessors"].size() - 1);
  }
  int indices(const std::vector<uint16_t>& v) {
    int bv = view(v.data(), v.size() * sizeof(uint16_t));
    doc["accessors"].push_back({{"bufferView", bv}, {"componentType", 5123}, {"count", v.size()}, {"type", "SCALAR"}});
    return int(doc["accessors"].size() - 1);
  }
  // A one-primitive mesh; normals/uvs/indices optional (empty = absent).
  int mesh(const std::string& name, const std::vector<float>& pos, const std::vector<float>& nrm = {},
           const std::vector<uint16_t>& idx = {}, int mode = 4, int material = -1,
           const std::vector<float>& uv = {}) {
    nlohmann::json prim = {{"attributes", {{"POSITION", floats(pos, 3)}}}, {"mode", mode}};
    if (!nrm.empty()) prim["attributes"]["NORMAL"] = floats(nrm, 3);
    if (!uv.empty()) prim["attributes"]["TEXCOORD_0"] = floats(uv, 2);
    if (!idx.empty()) prim["indices"] = indices(idx);
    if (material >= 0) prim["material"] = material;
    doc["meshes"].push_back({{"name", name}, {"primitives", {prim}}});
    return int(doc["meshes"].size() - 1);
  }
  // Adds a node (as a root of the scene unless `root` is false); returns its index.
  int node(nlohmann::json n, bool root = true) {
    doc["nodes"].push_back(n);
    int i = int(doc["nodes"].size() - 1);
    if (root) doc["scenes"][0]["nodes"].push_back(i);
    return i;
  }

  // Members written as raw text at the start of the top-level object ("\"key\": value, "),
  // for JSON that nlohmann's recursive dump could not write (hostile nesting).
  std::string raw_members;
  std::string spliced(const std::string& json) const { return "{" + raw_members + json.substr(1); }

  // Writes <dir>/<stem>.gltf + <stem>.bin; returns the .gltf path.
  std::filesystem::path write(const std::filesystem::path& dir, const std::string& stem = "model") {
    nlohmann::json d = doc;
    d["buffers"] = {{{"uri", stem + ".bin"}, {"byteLength", bin.size()}}};
    std::ofstream(dir / (stem + ".bin"), std::ios::binary).write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
    write_text(dir / (stem + ".gltf"), spliced(d.dump(1)));
    return dir / (stem + ".gltf");
  }

  // Writes a binary glTF (GLB container: header, JSON chunk, BIN chunk).
  std::filesystem::path write_glb(const std::filesystem::path& dir, const std::string& stem = "model") {
    nlohmann::json d = doc;
    d["buffers"] = {{{"byteLength", bin.size()}}};
    std::string json = spliced(d.dump());
    while (json.size() % 4) json.push_back(' ');
    std::vector<uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    std::string out;
    u32(out, 0x46546C67);  // "glTF"
    u32(out, 2);
    u32(out, uint32_t(12 + 8 + json.size() + 8 + b.size()));
    u32(out, uint32_t(json.size()));
    u32(out, 0x4E4F534A);  // "JSON"
    out += json;
    u32(out, uint32_t(b.size()));
    u32(out, 0x004E4942);  // "BIN\0"
    out.append(reinterpret_cast<const char*>(b.data()), b.size());
    write_text(dir / (stem + ".glb"), out);
    return dir / (stem + ".glb");
  }
};

// One CCW triangle in the z = 0 plane facing +z.
inline const std::vector<float> kTriPos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
inline const std::vector<float> kTriNrm = {0, 0, 1, 0, 0, 1, 0, 0, 1};

inline std::filesystem::path shared_scenes() { return std::filesystem::path(ZZ_SOURCE_DIR) / ".." / "shared" / "scenes"; }

}  // namespace zz::test
