// What the glTF loader reads from a file's JSON itself, beside tinygltf 2.7: the external
// files it names, and the checks and messages tinygltf gets wrong or words badly (a .bin
// longer than its buffer, a data: URI of the wrong length quoted whole, a spot light it
// does not name, an unreadable image reported twice).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace zz::gltf {

// The document, or a discarded value (is_object() false) where the text is nested deeper
// than kMaxJsonDepth or is not JSON: tinygltf then says what is wrong.
nlohmann::json parse_json(std::string_view text);

// Whether a buffer's or image's URI names a file (not empty, not a data: URI).
bool names_a_file(const std::string& uri);

// The external URIs of a glTF's JSON ("buffers" and "images"), in order; none when the
// document could not be read.
std::vector<std::string> external_uris(const nlohmann::json& doc);

// The external buffers of a glTF's JSON with their byteLength (those with a valid one).
std::vector<std::pair<std::string, uint64_t>> external_buffer_lengths(const nlohmann::json& doc);

// The bytes a base64 payload decodes to, if it is strict base64 (RFC 4648 §4: the
// alphabet, padded to a multiple of 4 characters); none otherwise.
std::optional<uint64_t> base64_decoded_size(std::string_view payload);

// Throws a zz::Error naming the first buffer whose data: URI holds another number of bytes
// than its byteLength: tinygltf says "Failed to decode" and quotes the whole payload,
// megabytes of base64.
void check_embedded_buffers(const nlohmann::json& doc, const std::string& file);

// `message` with each data: URI in it cut to its first characters: tinygltf quotes a URI it
// cannot decode whole.
std::string elide_data_uris(std::string message);

// tinygltf's "Spot light description not found." names no light: the first spot light
// of the file's KHR_lights_punctual without its "spot" object, and what is missing.
std::string explain_spot_light(std::string message, const nlohmann::json& doc);

// tinygltf's warnings without those about an image file it could not read ("File not
// found : x.png", then "Failed to load external 'uri' for image[0]"): the image loader
// reports the same image with its path, as an error or, with --allow-missing-textures, a
// warning of its own.
std::string without_image_read_warnings(const std::string& warning);

}  // namespace zz::gltf
