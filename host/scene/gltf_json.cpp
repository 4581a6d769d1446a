#include "scene/gltf_json.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "scene/gltf_file.h"  // json_nesting_depth

namespace zz::gltf {

nlohmann::json parse_json(std::string_view text) {
  if (json_nesting_depth(text) > kMaxJsonDepth) return nlohmann::json::value_t::discarded;
  return nlohmann::json::parse(text, nullptr, false);
}

bool names_a_file(const std::string& uri) { return !uri.empty() && uri.rfind("data:", 0) != 0; }

std::vector<std::string> external_uris(const nlohmann::json& j) {
  std::vector<std::string> uris;
  if (!j.is_object()) return uris;
  for (const char* array : {"buffers", "images"}) {
    const auto it = j.find(array);
    if (it == j.end() || !it->is_array()) continue;
    for (const nlohmann::json& item : *it)
      if (item.is_object() && item.contains("uri") && item["uri"].is_string() && names_a_file(item["uri"]))
        uris.push_back(item["uri"].get<std::string>());
  }
  return uris;
}

std::vector<std::pair<std::string, uint64_t>> external_buffer_lengths(const nlohmann::json& j) {
  std::vector<std::pair<std::string, uint64_t>> buffers;
  if (!j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) return buffers;
  for (const nlohmann::json& b : j["buffers"])
    if (b.is_object() && b.contains("uri") && b["uri"].is_string() && names_a_file(b["uri"]) &&
        b.contains("byteLength") && b["byteLength"].is_number_unsigned())
      buffers.emplace_back(b["uri"].get<std::string>(), b["byteLength"].get<uint64_t>());
  return buffers;
}

std::optional<uint64_t> base64_decoded_size(std::string_view payload) {
  if (payload.size() % 4 != 0) return std::nullopt;
  size_t pad = 0;
  while (pad < 2 && pad < payload.size() && payload[payload.size() - 1 - pad] == '=') ++pad;
  for (size_t i = 0; i + pad < payload.size(); ++i) {
    const char c = payload[i];
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/')) return std::nullopt;
  }
  return uint64_t(payload.size() / 4 * 3 - pad);
}

void check_embedded_buffers(const nlohmann::json& j, const std::string& file) {
  if (!j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) return;
  for (size_t i = 0; i < j["buffers"].size(); ++i) {
    const nlohmann::json& b = j["buffers"][i];
    if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string() || !b.contains("byteLength") ||
        !b["byteLength"].is_number_unsigned())
      continue;
    const std::string& uri = b["uri"].get_ref<const std::string&>();
    const size_t comma = uri.find(";base64,");
    if (uri.rfind("data:", 0) != 0 || comma == std::string::npos) continue;
    const std::optional<uint64_t> bytes = base64_decoded_size(std::string_view(uri).substr(comma + 8));
    const uint64_t length = b["byteLength"].get<uint64_t>();
    if (bytes && *bytes != length)
      throw Error(file + ": buffer " + std::to_string(i) + ": its data: URI holds " + std::to_string(*bytes) +
                  " bytes, but its byteLength says " + std::to_string(length));
  }
}

std::string elide_data_uris(std::string message) {
  constexpr size_t kKept = 48;
  for (size_t at = message.find("data:"); at != std::string::npos; at = message.find("data:", at + 1)) {
    size_t end = at;
    while (end < message.size() && !std::isspace(static_cast<unsigned char>(message[end]))) ++end;
    if (end - at <= kKept + 16) continue;
    const std::string note = "... (" + std::to_string(end - at) + " characters)";
    message.replace(at + kKept, end - at - kKept, note);
  }
  return message;
}

std::string explain_spot_light(std::string message, const nlohmann::json& j) {
  const std::string said = "Spot light description not found.";
  const size_t at = message.find(said);
  if (at == std::string::npos) return message;
  const nlohmann::json* lights = nullptr;
  if (j.is_object() && j.contains("extensions") && j["extensions"].is_object() &&
      j["extensions"].contains("KHR_lights_punctual") && j["extensions"]["KHR_lights_punctual"].is_object() &&
      j["extensions"]["KHR_lights_punctual"].contains("lights"))
    lights = &j["extensions"]["KHR_lights_punctual"]["lights"];
  if (!lights || !lights->is_array()) return message;
  for (size_t i = 0; i < lights->size(); ++i) {
    const nlohmann::json& l = (*lights)[i];
    if (!l.is_object() || l.value("type", nlohmann::json()) != "spot" || (l.contains("spot") && l["spot"].is_object()))
      continue;
    const std::string name = l.contains("name") && l["name"].is_string() ? " '" + l["name"].get<std::string>() + "'" : "";
    message.replace(at, said.size(), "light " + std::to_string(i) + name +
                                         " is a spot light without its \"spot\" object (KHR_lights_punctual requires "
                                         "it; its cone angles may be left out)");
    break;
  }
  return message;
}

std::string without_image_read_warnings(const std::string& warning) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < warning.size()) {
    const size_t end = std::min(warning.find('\n', start), warning.size());
    lines.push_back(warning.substr(start, end - start));
    start = end + 1;
  }
  std::string kept;
  for (size_t i = 0; i < lines.size(); ++i) {
    const bool image_unread = lines[i].rfind("Failed to load external 'uri' for image[", 0) == 0;
    const bool reason = i + 1 < lines.size() && lines[i + 1].rfind("Failed to load external 'uri' for image[", 0) == 0 &&
                        (lines[i].rfind("File not found : ", 0) == 0 || lines[i].rfind("File read error : ", 0) == 0);
    if (!image_unread && !reason) kept += lines[i] + "\n";
  }
  return kept;
}

}  // namespace zz::gltf
