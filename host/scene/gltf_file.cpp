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
#include <map>
#include <vector>

#include "core/error.h"
#include "core/file_io.h"
#include "scene/gltf_image.h"
#include "scene/gltf_json.h"

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
  return -1;
}

// How a URI's escapes are read: as tinygltf 2.7 reads them (the key its path callback is
// called with: '+' as a space, an HTML form's reading, and a bad hex digit as 0), or as
// the file the URI names (RFC 3986 §2.1: "C++.png" is itself, and a '%' not followed by
// two hex digits, or one that would decode to a NUL byte, is itself: "grey_50%.png" named
// "grey_50\0ng", which no file is and which cut the error message short).
enum class UriReading { Tinygltf, File };

std::string percent_decode(const std::string& uri, UriReading reading) {
  const bool tinygltf = reading == UriReading::Tinygltf;
  std::string decoded;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+' && tinygltf) {
      decoded += ' ';
    } else if (uri[i] == '%' && i + 2 < uri.size()) {
      const int hi = hex_digit(uri[i + 1]), lo = hex_digit(uri[i + 2]);
      const int byte = tinygltf ? std::max(hi, 0) << 4 | std::max(lo, 0) : hi < 0 || lo < 0 ? 0 : hi << 4 | lo;
      if (!tinygltf && byte == 0) {
        decoded += uri[i];
        continue;
      }
      decoded += char(byte);
      i += 2;
    } else {
      decoded += uri[i];
    }
  }
  return decoded;
}

// tinygltf 2.7 decodes a URI with '+' as a space and then looks for the file next to the
// glTF and, failing that, in the working directory. Its path callback is handed the path it
// made and returns the one it reads: the file the URI names next to the glTF, and nothing
// from the working directory, where a render on another machine or folder would find
// another file or none.
class UriResolver {
 public:
  UriResolver(const std::filesystem::path& gltf, const nlohmann::json& doc) : gltf_(gltf), doc_(doc) {}

  std::string resolve(const std::string& tinygltf_path) {
    if (!map_) build();
    const auto it = map_->find(tinygltf_path);
    if (it == map_->end()) return {};  // the working directory's copy: not found
    if (!it->second) throw Error(gltf_.string() + ": URIs '" + ambiguous_[it->first].first + "' and '" +
                                 ambiguous_[it->first].second + "' name different files that tinygltf 2.7 cannot tell apart (it reads '+' as a space and a '%' escape's bad digits as 0); rename one");
    std::error_code ec;
    if (!std::filesystem::exists(*it->second, ec)) missing_.push_back({percent_decode(first_uri_[it->first], UriReading::Tinygltf), *it->second});
    return *it->second;
  }

  // The byteLength of the external buffer stored in `file` (as resolve() returned it);
  // none when no buffer names it, or buffers naming it disagree.
  std::optional<uint64_t> buffer_length(const std::string& file) {
    if (!map_) build();
    const auto it = buffer_length_.find(file);
    if (it == buffer_length_.end()) return std::nullopt;
    return it->second;
  }

  // tinygltf's "File not found : <its decoding>" names the file the URI names.
  std::string explain(std::string message) const {
    for (const auto& [tinygltf_name, file] : missing_) {
      const std::string said = "File not found : " + tinygltf_name;
      if (const size_t at = message.find(said); at != std::string::npos) message.replace(at, said.size(), "file not found: " + file);
    }
    return message;
  }

 private:
  // tinygltf's JoinPath(base_dir, decoded): the key its callback is called with.
  std::string tinygltf_key(const std::string& uri) const {
    const std::string base = gltf_.parent_path().string();
    const std::string decoded = percent_decode(uri, UriReading::Tinygltf);
    if (base.empty()) return decoded;
    return base.back() == '/' ? base + decoded : base + "/" + decoded;
  }

  void build() {
    map_.emplace();
    for (const std::string& uri : external_uris(doc_)) {
      const std::string key = tinygltf_key(uri);
      const std::string file = external_file(gltf_, uri)->string();
      const auto [it, fresh] = map_->emplace(key, file);
      if (!fresh && it->second && *it->second != file) {
        ambiguous_[key] = {first_uri_[key], uri};
        it->second.reset();
      }
      first_uri_.emplace(key, uri);
    }
    for (const auto& [uri, length] : external_buffer_lengths(doc_)) {
      const std::string file = external_file(gltf_, uri)->string();
      const auto [it, fresh] = buffer_length_.emplace(file, length);
      if (!fresh && it->second != length) it->second.reset();
    }
  }

  std::filesystem::path gltf_;
  const nlohmann::json& doc_;
  std::optional<std::map<std::string, std::optional<std::string>>> map_;
  std::map<std::string, std::string> first_uri_;
  std::map<std::string, std::pair<std::string, std::string>> ambiguous_;
  std::vector<std::pair<std::string, std::string>> missing_;
  std::map<std::string, std::optional<uint64_t>> buffer_length_;
};

std::string resolve_uri_path(const std::string& tinygltf_path, void* resolver) {
  return static_cast<UriResolver*>(resolver)->resolve(tinygltf_path);
}

// tinygltf's reader of the .bin files and images a glTF names. A .bin longer than its
// buffer's byteLength is valid glTF (the validator only refuses a shorter one; Khronos's
// SimpleMaterial sample pads its .bin), but tinygltf 2.7 wants the sizes equal: it is
// handed the buffer's bytes, as a .glb's longer BIN chunk already is.
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* resolver) {
  std::string why;
  if (!read_regular_file(path, kMaxFileBytes, out, &why)) {
    if (err) *err += why + "\n";  // tinygltf names the file
    return false;
  }
  if (const std::optional<uint64_t> length = static_cast<UriResolver*>(resolver)->buffer_length(path);
      length && *length < out->size())
    out->resize(size_t(*length));
  return true;
}

}  // namespace

std::optional<std::filesystem::path> external_file(const std::filesystem::path& gltf, const std::string& uri) {
  if (!names_a_file(uri)) return std::nullopt;
  return gltf.parent_path() / percent_decode(uri, UriReading::File);
}

std::vector<std::filesystem::path> external_files(const std::filesystem::path& gltf) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(gltf, ec)) return files;  // a FIFO would block the read
  std::vector<unsigned char> bytes;
  std::string_view json_text;
  std::ifstream in(gltf, std::ios::binary);
  char magic[4] = {};
  if (in.read(magic, 4) && std::memcmp(magic, "glTF", 4) == 0) {  // binary by its content, as read_gltf_model
    // The header and the JSON chunk only: the buffers that follow can be hundreds of MB.
    bytes.resize(20);
    std::memcpy(bytes.data(), magic, 4);
    if (!in.read(reinterpret_cast<char*>(bytes.data() + 4), 16)) return files;
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
  for (const std::string& uri : external_uris(parse_json(json_text))) files.push_back(*external_file(gltf, uri));
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

  // A .glb starts with the magic "glTF" and JSON with '{' (after blanks): the content
  // decides, so a binary glTF saved as .gltf (or the other way round) still loads.
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (binary) require_gltf2_container(bytes, file);
  const std::string_view json =
      binary ? glb_json(bytes) : std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (json_nesting_depth(json) > kMaxJsonDepth)
    throw Error(file + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels; not a glTF scene");
  const nlohmann::json doc = parse_json(json);
  check_embedded_buffers(doc, file);

  tinygltf::TinyGLTF gltf;
  gltf.SetImageLoader(keep_encoded, &model);  // it checks an image's bufferView against the model's buffers
  UriResolver resolver(path, doc);
  gltf.SetFsCallbacks({file_exists, resolve_uri_path, read_whole_file, tinygltf::WriteWholeFile, &resolver});
  std::string err;
  // Relative URIs resolve against the file's folder, as tinygltf's *FromFile calls do.
  const std::string base_dir = path.parent_path().string();
  bool ok = false;
  try {
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, warning, bytes.data(), unsigned(bytes.size()), base_dir)
                : gltf.LoadASCIIFromString(&model, &err, warning, reinterpret_cast<const char*>(bytes.data()),
                                           unsigned(bytes.size()), base_dir);
  } catch (const Error&) {  // the URI resolver's
    throw;
  } catch (const std::exception& e) {  // tinygltf's JSON parser or an allocation
    throw Error(file + ": cannot parse glTF (" + e.what() + ")");
  }
  if (!ok) {
    std::string msg = err.empty() ? "cannot parse glTF" : explain_spot_light(elide_data_uris(resolver.explain(err)), doc);
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    throw Error(file + ": " + msg);
  }
  if (warning) *warning = elide_data_uris(without_image_read_warnings(*warning));
  require_gltf2_asset(model, file);
}

}  // namespace zz::gltf
