#include "scene/gltf_file.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/file_io.h"
#include "scene/gltf_image.h"

namespace zz::gltf {

int json_nesting_depth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit) return deepest;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

namespace {

uint32_t le32(const std::vector<unsigned char>& b, size_t at) {
  return uint32_t(b[at]) | uint32_t(b[at + 1]) << 8 | uint32_t(b[at + 2]) << 16 | uint32_t(b[at + 3]) << 24;
}

// The JSON a .glb carries: its first chunk (glTF 2.0 §4.4.3), when the header is sound;
// otherwise empty, and tinygltf says what is wrong with the file.
std::string_view glb_json(const std::vector<unsigned char>& bytes) {
  if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) return {};
  const uint32_t length = le32(bytes, 12);
  if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0 || length > bytes.size() - 20) return {};
  return {reinterpret_cast<const char*>(bytes.data() + 20), length};
}

// tinygltf's own callbacks take a file it cannot open for a missing one ("File not found"
// for a .bin the user may not read): a file that exists is found, and reading it says why
// it fails.
bool file_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

// tinygltf's reader of the .bin files and images a glTF names.
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::string why;
  if (read_regular_file(path, kMaxFileBytes, out, &why)) return true;
  if (err) *err += why + "\n";  // tinygltf names the file
  return false;
}

// glTF 1.0 (and a future 3.x) is another format: its .glb has container version 1, which
// tinygltf reports as an invalid binary, and its .gltf parses without a word.
void require_gltf2_container(const std::vector<unsigned char>& bytes, const std::string& file) {
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), "glTF", 4) == 0 && le32(bytes, 4) != 2)
    throw Error(file + ": GLB container version " + std::to_string(le32(bytes, 4)) + "; only glTF 2.0 is supported");
}

void require_gltf2_asset(const tinygltf::Model& model, const std::string& file) {
  // A 2.0 reader loads 2.x assets unless their minVersion asks for more than 2.0.
  if (model.asset.version.rfind("2.", 0) != 0)
    throw Error(file + ": glTF version '" + model.asset.version + "'; only glTF 2.0 is supported");
  if (!model.asset.minVersion.empty() && model.asset.minVersion != "2.0")
    throw Error(file + ": glTF minVersion '" + model.asset.minVersion + "'; only glTF 2.0 is supported");
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return 0;  // as tinygltf: a bad digit counts as 0
}

}  // namespace

std::optional<std::filesystem::path> external_file(const std::filesystem::path& gltf, const std::string& uri) {
  if (uri.empty() || uri.rfind("data:", 0) == 0) return std::nullopt;
  std::string decoded;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      decoded += ' ';
    } else if (uri[i] == '%' && i + 2 < uri.size()) {
      decoded += char(hex_digit(uri[i + 1]) << 4 | hex_digit(uri[i + 2]));
      i += 2;
    } else {
      decoded += uri[i];
    }
  }
  return gltf.parent_path() / decoded;
}

std::vector<std::filesystem::path> external_files(const std::filesystem::path& gltf) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(gltf, ec)) return files;  // a FIFO would block the read
  std::vector<unsigned char> bytes;
  std::string_view json_text;
  if (lowercase_extension(gltf) == ".glb") {
    // The header and the JSON chunk only: the buffers that follow can be hundreds of MB.
    std::ifstream in(gltf, std::ios::binary);
    bytes.resize(20);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), 20)) return files;
    const uintmax_t size = std::filesystem::file_size(gltf, ec);
    if (ec || le32(bytes, 12) > size - 20) return files;  // the header's claim, checked before any allocation
    bytes.resize(20 + size_t(le32(bytes, 12)));
    if (!in.read(reinterpret_cast<char*>(bytes.data() + 20), std::streamsize(bytes.size() - 20))) return files;
    json_text = glb_json(bytes);
  } else {
    std::string why;
    if (!read_regular_file(gltf.string(), kMaxFileBytes, &bytes, &why)) return files;
    json_text = std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  }
  if (json_nesting_depth(json_text) > kMaxJsonDepth) return files;
  const nlohmann::json j = nlohmann::json::parse(json_text, nullptr, false);
  if (!j.is_object()) return files;
  for (const char* array : {"buffers", "images"}) {
    const auto it = j.find(array);
    if (it == j.end() || !it->is_array()) continue;
    for (const nlohmann::json& item : *it) {
      if (!item.is_object() || !item.contains("uri") || !item["uri"].is_string()) continue;
      if (std::optional<std::filesystem::path> f = external_file(gltf, item["uri"].get<std::string>()))
        files.push_back(std::move(*f));
    }
  }
  return files;
}

void read_gltf_model(const std::filesystem::path& path, tinygltf::Model& model, std::string* warning) {
  const std::string file = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(file + ": is a directory, not a glTF file");
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status))
    throw Error(file + ": " + (ec && ec != std::errc::no_such_file_or_directory ? ec.message() : "file not found"));
  if (!std::filesystem::is_regular_file(status)) throw Error(file + ": not a regular file");
  // One read of the whole file, as of its buffers: a .glb holds them, often hundreds of MB.
  const std::vector<unsigned char> bytes = read_regular_file(file, kMaxFileBytes);
  if (bytes.empty()) throw Error(file + ": empty file");

  const std::string ext = lowercase_extension(path);
  const bool binary = ext == ".glb";
  if (binary) require_gltf2_container(bytes, file);
  const std::string_view json =
      binary ? glb_json(bytes) : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (json_nesting_depth(json) > kMaxJsonDepth)
    throw Error(file + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels; not a glTF scene");

  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(keep_encoded, &model);  // it checks an image's bufferView against the model's buffers
  gltf.SetFsCallbacks({file_exists, tinygltf::ExpandFilePath, read_whole_file, tinygltf::WriteWholeFile, nullptr});
  std::string err;
  // Relative URIs resolve against the file's folder, as tinygltf's *FromFile calls do.
  const std::string base_dir = path.parent_path().string();
  bool ok = false;
  try {
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, warning, bytes.data(), unsigned(bytes.size()), base_dir)
                : gltf.LoadASCIIFromString(&model, &err, warning, reinterpret_cast<const char*>(bytes.data()),
                                           unsigned(bytes.size()), base_dir);
  } catch (const std::exception& e) {  // tinygltf's JSON parser or an allocation
    throw Error(file + ": cannot parse glTF (" + e.what() + ")");
  }
  if (!ok) {
    std::string msg = err.empty() ? "cannot parse glTF" : err;
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    throw Error(file + ": " + msg);
  }
  require_gltf2_asset(model, file);
}

}  // namespace zz::gltf
