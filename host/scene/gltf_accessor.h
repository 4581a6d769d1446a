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

// Throws unless accessor `index` has a component type glTF 2.0 allows for the vertex
// attribute `attribute` (section 3.7.2.1: POSITION, NORMAL and TANGENT float; TEXCOORD_n
// float or normalized unsigned byte / short), or, with KHR_mesh_quantization
// (`quantized`), the integer types that extension adds. Other attributes are not checked.
void check_attribute_type(const tinygltf::Model& model, int index, const std::string& attribute, bool quantized,
                          const std::string& where);

// An index accessor (SCALAR of unsigned byte/short/int) as 32-bit indices.
std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index, const std::string& where);

}  // namespace zz::gltf
