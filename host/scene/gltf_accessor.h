// Bounds-checked reading of glTF accessors. Every index into accessors, bufferViews and
// buffers, and every byte range, is validated before use: malformed or hostile files
// produce a zz::Error, never an out-of-bounds read (the loaders are fuzz targets).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace zz::gltf {

// Accessor `index` as `components` floats per element (normalized integers mapped per
// the glTF spec, sparse substitution applied). `where` prefixes error messages.
std::vector<float> read_floats(const tinygltf::Model& model, int index, int components,
                               const std::string& where);

// An index accessor (SCALAR of unsigned byte/short/int) as 32-bit indices.
std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index, const std::string& where);

}  // namespace zz::gltf
