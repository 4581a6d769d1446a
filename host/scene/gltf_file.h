// A .gltf or .glb file -> tinygltf::Model, with what tinygltf itself cannot survive
// checked first: its JSON values (extras, extensions) are converted by recursion, one stack
// frame per level, so 20 000 nested arrays in 40 kB of text overflowed the stack.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tinygltf {
class Model;
}

namespace zz::gltf {

// Deepest JSON nesting a scene may have: a glTF needs 10 or so; hostile text is refused
// long before the recursion could reach the end of a thread's stack (sanitized builds
// included, whose frames are several times larger).
inline constexpr int kMaxJsonDepth = 512;

// Largest file a glTF, its buffers or images may be: a buffer's byteLength is a uint32 in
// practice (tinygltf's own limit on a .glb).
inline constexpr uintmax_t kMaxFileBytes = uintmax_t(1) << 32;

// Largest number of open '[' / '{' in `text`, outside strings (JSON's escapes honoured).
// Stops counting once past `limit`.
int json_nesting_depth(std::string_view text, int limit = kMaxJsonDepth);

// The file an external buffer's or image's URI names, as the loader reads it: relative to
// the glTF's folder (an absolute path as it is) and percent-decoded ("My%20Wood.png" is My
// Wood.png, "C++.png" is itself), never looked for in the working directory. None for a URI that names no file
// (empty, or a data: URI holding the bytes).
std::optional<std::filesystem::path> external_file(const std::filesystem::path& gltf, const std::string& uri);

// The external files (buffers, images) `gltf` names, read from its JSON alone: a .glb's
// header and JSON chunk, not its buffers. For checks before a batch loads its scenes, so it
// never throws: whatever it cannot read is left out, and loading the file says why.
std::vector<std::filesystem::path> external_files(const std::filesystem::path& gltf);

// Reads and parses `path` (binary glTF by its magic "glTF", whatever its extension, else
// glTF JSON); zz::Error naming the file on anything wrong. Images keep their encoded bytes
// (gltf_image.h). Warnings from tinygltf go to *warning.
void read_gltf_model(const std::filesystem::path& path, tinygltf::Model& model, std::string* warning);

}  // namespace zz::gltf
