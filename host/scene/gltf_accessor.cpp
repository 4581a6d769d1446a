#include "scene/gltf_accessor.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>

#include "core/error.h"

namespace zz::gltf {
namespace {

// Far above any real asset; keeps every size product below 2^64.
constexpr uint64_t kMaxElements = uint64_t(1) << 31;
// Accessors without a bufferView are all zeros (plus sparse values) and cost no file
// bytes, so their size is capped separately.
constexpr uint64_t kMaxZeroElements = uint64_t(1) << 24;

size_t component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

// One component; normalized integers follow glTF 2.0 section 3.11 (max(c / MAX, -1)).
float fetch(const uint8_t* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v; std::memcpy(&v, p, 1);
      return normalized ? std::max(float(v) / 127.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      uint8_t v; std::memcpy(&v, p, 1);
      return normalized ? float(v) / 255.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v; std::memcpy(&v, p, 2);
      return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v; std::memcpy(&v, p, 2);
      return normalized ? float(v) / 65535.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v; std::memcpy(&v, p, 4);
      return float(v);
    }
    default: {
      float v; std::memcpy(&v, p, 4);
      return v;
    }
  }
}

uint32_t fetch_index(const uint8_t* p, int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return v; }
    default: { uint32_t v; std::memcpy(&v, p, 4); return v; }
  }
}

// A validated strided byte range: element i starts at base + i * stride.
struct Range {
  const uint8_t* base = nullptr;  // null = all zeros (accessor without bufferView)
  uint64_t stride = 0;
};

// Checks that `count` elements of `elem` bytes at `offset` inside bufferView `view`
// (tightly packed when `packed`) lie inside the view and its buffer.
Range view_range(const tinygltf::Model& model, int view, uint64_t offset, uint64_t count,
                 uint64_t elem, bool packed, const std::string& where) {
  if (view < 0 || size_t(view) >= model.bufferViews.size())
    throw Error(where + ": bufferView " + std::to_string(view) + " out of range");
  const tinygltf::BufferView& bv = model.bufferViews[size_t(view)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
    throw Error(where + ": buffer " + std::to_string(bv.buffer) + " out of range");
  const std::vector<unsigned char>& data = model.buffers[size_t(bv.buffer)].data;
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
    throw Error(where + ": bufferView " + std::to_string(view) + " exceeds its buffer (" +
                std::to_string(data.size()) + " bytes; missing or truncated .bin?)");
  Range r;
  r.stride = (packed || bv.byteStride == 0) ? elem : uint64_t(bv.byteStride);
  if (r.stride < elem || r.stride > 4096)
    throw Error(where + ": bad byteStride in bufferView " + std::to_string(view));
  if (count > 0) {
    uint64_t end = offset + (count - 1) * r.stride + elem;  // no overflow: count < 2^31
    if (offset > bv.byteLength || end > bv.byteLength)
      throw Error(where + ": accessor data exceeds bufferView " + std::to_string(view));
  }
  r.base = data.data() + bv.byteOffset + offset;
  return r;
}

}  // namespace

std::vector<float> read_floats(const tinygltf::Model& model, int index, int components,
                               const std::string& where) {
  if (index < 0 || size_t(index) >= model.accessors.size())
    throw Error(where + ": accessor " + std::to_string(index) + " out of range");
  const tinygltf::Accessor& acc = model.accessors[size_t(index)];
  const int n = type_components(acc.type);
  const size_t csize = component_size(acc.componentType);
  if (n != components || csize == 0)
    throw Error(where + ": accessor " + std::to_string(index) + " has type/component type " +
                std::to_string(acc.type) + "/" + std::to_string(acc.componentType) + ", expected " +
                std::to_string(components) + " components");
  if (uint64_t(acc.count) > kMaxElements)
    throw Error(where + ": accessor " + std::to_string(index) + " count too large");
  const uint64_t elem = uint64_t(n) * csize;
  // Validate the byte range before allocating: a hostile count must not cost memory.
  Range r;
  if (acc.bufferView >= 0) r = view_range(model, acc.bufferView, acc.byteOffset, acc.count, elem, false, where);
  else if (acc.count > kMaxZeroElements)
    throw Error(where + ": accessor " + std::to_string(index) + " without bufferView is too large");
  std::vector<float> out(acc.count * size_t(n), 0.0f);
  if (acc.bufferView >= 0) {
    for (size_t i = 0; i < acc.count; ++i)
      for (int c = 0; c < n; ++c)
        out[i * n + c] = fetch(r.base + i * r.stride + c * csize, acc.componentType, acc.normalized);
  }
  if (acc.sparse.isSparse) {
    // glTF 2.0 section 3.6.2.3: listed elements replace the dense (or zero) values.
    const uint64_t count = uint64_t(std::max(acc.sparse.count, 0));
    const int itype = acc.sparse.indices.componentType;
    if (count > acc.count || (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                              itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                              itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
      throw Error(where + ": bad sparse accessor " + std::to_string(index));
    Range ri = view_range(model, acc.sparse.indices.bufferView,
                          uint64_t(std::max(acc.sparse.indices.byteOffset, 0)), count,
                          component_size(itype), true, where);
    Range rv = view_range(model, acc.sparse.values.bufferView,
                          uint64_t(std::max(acc.sparse.values.byteOffset, 0)), count, elem, true, where);
    for (uint64_t i = 0; i < count; ++i) {
      uint32_t target = fetch_index(ri.base + i * ri.stride, itype);
      if (target >= acc.count) throw Error(where + ": sparse index out of range");
      for (int c = 0; c < n; ++c)
        out[size_t(target) * n + c] =
            fetch(rv.base + i * rv.stride + c * csize, acc.componentType, acc.normalized);
    }
  }
  return out;
}

void check_attribute_type(const tinygltf::Model& model, int index, const std::string& attribute, bool quantized,
                          const std::string& where) {
  if (index < 0 || size_t(index) >= model.accessors.size())
    throw Error(where + ": accessor " + std::to_string(index) + " out of range");
  const tinygltf::Accessor& acc = model.accessors[size_t(index)];
  const int t = acc.componentType;
  if (t == TINYGLTF_COMPONENT_TYPE_FLOAT) return;
  const bool byte_or_short = t == TINYGLTF_COMPONENT_TYPE_BYTE || t == TINYGLTF_COMPONENT_TYPE_SHORT;
  const bool unsigned_byte_or_short =
      t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  bool allowed = false;
  if (attribute.rfind("TEXCOORD_", 0) == 0)
    allowed = (unsigned_byte_or_short && acc.normalized) || (quantized && (byte_or_short || unsigned_byte_or_short));
  else if (attribute == "POSITION")
    allowed = quantized && (byte_or_short || unsigned_byte_or_short);
  else if (attribute == "NORMAL" || attribute == "TANGENT")
    allowed = quantized && byte_or_short && acc.normalized;
  else
    return;
  if (!allowed)
    throw Error(where + ": accessor " + std::to_string(index) + " has component type " + std::to_string(t) +
                (acc.normalized ? " (normalized)" : "") + ", which glTF 2.0 does not allow for " + attribute +
                (quantized ? "" : " without KHR_mesh_quantization"));
}

std::vector<uint32_t> read_indices(const tinygltf::Model& model, int index, const std::string& where) {
  if (index < 0 || size_t(index) >= model.accessors.size())
    throw Error(where + ": index accessor " + std::to_string(index) + " out of range");
  const tinygltf::Accessor& acc = model.accessors[size_t(index)];
  const int t = acc.componentType;
  if (acc.type != TINYGLTF_TYPE_SCALAR ||
      (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    throw Error(where + ": index accessor " + std::to_string(index) + " is not unsigned scalar");
  if (acc.sparse.isSparse) {
    // Rare for indices; reuse the float path only where it is exact (< 2^24).
    std::vector<float> f = read_floats(model, index, 1, where);
    std::vector<uint32_t> out(f.size());
    for (size_t i = 0; i < f.size(); ++i) {
      if (!(f[i] >= 0.0f && f[i] < 16777216.0f)) throw Error(where + ": sparse index too large");
      out[i] = uint32_t(f[i]);
    }
    return out;
  }
  if (uint64_t(acc.count) > kMaxElements)
    throw Error(where + ": index accessor " + std::to_string(index) + " count too large");
  if (acc.bufferView < 0) {
    if (acc.count > kMaxZeroElements) throw Error(where + ": index accessor without bufferView is too large");
    return std::vector<uint32_t>(acc.count, 0);
  }
  if (size_t(acc.bufferView) < model.bufferViews.size() && model.bufferViews[size_t(acc.bufferView)].byteStride != 0)
    throw Error(where + ": index accessor " + std::to_string(index) + " reads bufferView " +
                std::to_string(acc.bufferView) +
                ", which has a byteStride: index data must be tightly packed (glTF 2.0: byteStride is for vertex attributes only)");
  Range r = view_range(model, acc.bufferView, acc.byteOffset, acc.count, component_size(t), false, where);
  std::vector<uint32_t> out(acc.count, 0);
  for (size_t i = 0; i < acc.count; ++i) out[i] = fetch_index(r.base + i * r.stride, t);
  return out;
}

}  // namespace zz::gltf
