// Storage types of the BVH (kept out of bvh.h's public section, but complete there so
// that std::vector<Node> has a usable destructor in every translation unit).
#pragma once

#include <cstdint>

#include "core/simd.h"

namespace zz {

// A 4-wide node (Embree-style BVH4, Dammertz et al. 2008 "Shallow Bounding Volume
// Hierarchies"): the children's boxes in SoA so that one ray tests all four with one SSE
// slab test, and a packet tests one child per step with broadcast planes. 128 bytes,
// two cache lines.
struct alignas(64) Bvh4Node {
  float lo_x[4], lo_y[4], lo_z[4];
  float hi_x[4], hi_y[4], hi_z[4];
  uint32_t child[4];  // kLeafBit set: index of a BvhTriBlock; else a node index
  uint32_t count;     // valid children, packed first (2..4, or 1 for a one-leaf tree)
  uint32_t pad[3];

  static constexpr uint32_t kLeafBit = 0x80000000u;
};
static_assert(sizeof(Bvh4Node) == 128);

// A leaf: up to four triangles in SoA, so that one ray tests all of them at once (and a
// packet broadcasts one at a time). Unused lanes have prim = -1 and NaN vertices, which
// the watertight kernel never reports as a hit. prim is the original triangle index (the
// tie-break key for equal t).
struct alignas(16) BvhTriBlock {
  float v0x[4], v0y[4], v0z[4];
  float v1x[4], v1y[4], v1z[4];
  float v2x[4], v2y[4], v2z[4];
  int32_t prim[4];
};
static_assert(sizeof(BvhTriBlock) == 160);

// Deepest binary tree the builder produces; traversal stacks are sized from it (a BVH4
// level pushes at most 3 entries and spans at least one binary level).
inline constexpr int kBvhMaxDepth = 96;
inline constexpr int kBvhStackSize = 3 * kBvhMaxDepth + 4;

}  // namespace zz
