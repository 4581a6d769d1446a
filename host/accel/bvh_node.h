// Storage types of the BVH (kept out of bvh.h's public section, but complete there so
// that std::vector<Node> has a usable destructor in every translation unit).
#pragma once

#include <cstdint>

#include "core/simd.h"

namespace zz {

// A 32-byte binary node: two of them fill one 64-byte cache line, and a node's children
// are always adjacent (first, first + 1), so the parent tests both with one fetch.
struct alignas(32) BvhNode {
  float lo[3];
  uint32_t first;  // leaf: first triangle slot; interior: index of the left child
  float hi[3];
  uint32_t meta;   // leaf: count << 2 | 3; interior: split axis (0..2)

  bool leaf() const { return (meta & 3u) == 3u; }
  uint32_t count() const { return meta >> 2; }
  uint32_t axis() const { return meta & 3u; }
};
static_assert(sizeof(BvhNode) == 32);

// The three vertices of a triangle in leaf order, 16-byte rows so that the SSE kernel
// loads a vertex with one aligned load and broadcasts its coordinates. The fourth word
// of row 0 carries the original triangle index (the tie-break key).
struct alignas(16) BvhTriangle {
  float v0[3];
  int32_t prim;
  float v1[3];
  float pad1;
  float v2[3];
  float pad2;
};
static_assert(sizeof(BvhTriangle) == 48);

// Deepest tree the builder produces; traversal stacks hold this many entries.
inline constexpr int kBvhMaxDepth = 96;

}  // namespace zz
