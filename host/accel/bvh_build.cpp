// Binned SAH build (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", 2007): 32 centroid bins per axis, leaves chosen by the SAH itself.
// Single-threaded and free of unordered containers, so the tree is a pure function of
// the input.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "accel/bvh.h"

namespace zz {
namespace {

constexpr int kBins = 32;

// The bin of a centroid coordinate c in [lo, lo + extent]. Divides by the extent instead
// of multiplying by kBins / extent: for a denormal extent that quotient overflows to +Inf
// and (c - lo) * Inf is NaN for c = lo (found by fuzzing). NaN and negatives map to bin 0.
inline int centroid_bin(float c, float lo, float extent) {
  const float t = (c - lo) / extent * (float(kBins) * 0.99999f);
  return t > 0.0f ? std::min(kBins - 1, int(std::min(t, float(kBins)))) : 0;
}
constexpr uint32_t kMaxLeafSize = 4;  // one SoA block (BvhTriBlock)
// SAH constants: cost of one traversal step relative to one triangle test. A leaf's
// triangles are tested four at a time (single rays) and its block is one fetch, so the
// leaf-or-split decision prices a triangle at half a traversal step: measured with
// tools/bench_traversal, 5-8% faster than 1.0 for single rays, same for packets, and
// blocks fill 3 of 4 lanes instead of 2.
constexpr float kTraversalCost = 1.0f;
constexpr float kTriangleCost = 1.0f;
constexpr float kLeafTriangleCost = 0.5f;
// From this depth on, split by object median so the tree depth stays bounded.
constexpr int kMedianDepth = kBvhMaxDepth - 40;

// The binary tree of the build: 32 bytes, children adjacent (first, first + 1).
struct BinNode {
  float lo[3];
  uint32_t first;  // leaf: first ref; interior: left child
  float hi[3];
  uint32_t meta;   // leaf: count << 2 | 3; interior: split axis
  bool leaf() const { return (meta & 3u) == 3u; }
  uint32_t count() const { return meta >> 2; }
};

struct Box {
  glm::vec3 lo{kInfinity}, hi{-kInfinity};
  void grow(glm::vec3 p) { lo = glm::min(lo, p); hi = glm::max(hi, p); }
  void grow(const Box& b) { lo = glm::min(lo, b.lo); hi = glm::max(hi, b.hi); }
  float area() const {
    glm::vec3 e = hi - lo;
    return (e.x < 0.0f) ? 0.0f : 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

struct Builder {
  std::vector<Box> tri_box;
  std::vector<glm::vec3> centroid;
  std::vector<uint32_t> refs;  // input triangle indices, partitioned in place
  std::vector<BinNode>* nodes;
  BvhBuildStats stats;

  void make_leaf(BinNode& node, uint32_t begin, uint32_t end) {
    node.first = begin;
    node.meta = ((end - begin) << 2) | 3u;
    ++stats.leaf_count;
  }

  // Builds the subtree of nodes[index] over refs[begin, end).
  void build(uint32_t index, uint32_t begin, uint32_t end, int depth) {
    stats.max_depth = std::max<size_t>(stats.max_depth, size_t(depth));
    Box bounds, cbounds;
    for (uint32_t i = begin; i < end; ++i) {
      bounds.grow(tri_box[refs[i]]);
      cbounds.grow(centroid[refs[i]]);
    }
    {
      BinNode& node = (*nodes)[index];
      for (int k = 0; k < 3; ++k) node.lo[k] = bounds.lo[k], node.hi[k] = bounds.hi[k];
    }
    uint32_t n = end - begin;
    if (n == 1) return make_leaf((*nodes)[index], begin, end);

    // Best split over all three axes; cost in units of kTriangleCost * parent area.
    float best_cost = kInfinity;
    int best_axis = -1, best_bin = 0;
    glm::vec3 extent = cbounds.hi - cbounds.lo;
    if (depth < kMedianDepth) {
      for (int axis = 0; axis < 3; ++axis) {
        if (!(extent[axis] > 0.0f)) continue;
        std::array<Box, kBins> bin_box;
        std::array<uint32_t, kBins> bin_count{};
        for (uint32_t i = begin; i < end; ++i) {
          const int b = centroid_bin(centroid[refs[i]][axis], cbounds.lo[axis], extent[axis]);
          bin_box[b].grow(tri_box[refs[i]]);
          ++bin_count[b];
        }
        // Sweep from the right, then from the left (SAH: A_L N_L + A_R N_R).
        std::array<float, kBins> right_cost{};
        Box acc;
        uint32_t count = 0;
        for (int b = kBins - 1; b > 0; --b) {
          acc.grow(bin_box[b]);
          count += bin_count[b];
          right_cost[b] = acc.area() * float(count);
        }
        acc = Box{};
        count = 0;
        for (int b = 0; b < kBins - 1; ++b) {
          acc.grow(bin_box[b]);
          count += bin_count[b];
          if (count == 0 || count == n) continue;
          float cost = acc.area() * float(count) + right_cost[b + 1];
          if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = b;
        }
      }
    }
    float parent_area = bounds.area();
    float leaf_cost = kLeafTriangleCost * float(n);
    float split_cost = parent_area > 0.0f
                           ? kTraversalCost + kTriangleCost * best_cost / parent_area
                           : kTraversalCost + leaf_cost;
    if (n <= kMaxLeafSize && (best_axis < 0 || leaf_cost <= split_cost))
      return make_leaf((*nodes)[index], begin, end);

    uint32_t mid;
    int axis;
    if (best_axis >= 0) {
      axis = best_axis;
      const float lo = cbounds.lo[axis], ext = extent[axis];
      auto left_of = [&](uint32_t r) { return centroid_bin(centroid[r][axis], lo, ext) <= best_bin; };
      mid = uint32_t(std::partition(refs.begin() + begin, refs.begin() + end, left_of) -
                     refs.begin());
    } else {
      // All centroids coincide (or the depth cap): halve the range by centroid order.
      axis = int(std::max_element(&extent[0], &extent[0] + 3) - &extent[0]);
      mid = begin + n / 2;
      std::nth_element(refs.begin() + begin, refs.begin() + mid, refs.begin() + end,
                       [&](uint32_t a, uint32_t b) {
                         float ca = centroid[a][axis], cb = centroid[b][axis];
                         return ca < cb || (ca == cb && a < b);
                       });
    }
    uint32_t child = uint32_t(nodes->size());
    nodes->resize(nodes->size() + 2);
    (*nodes)[index].first = child;
    (*nodes)[index].meta = uint32_t(axis);
    build(child, begin, mid, depth + 1);
    build(child + 1, mid, end, depth + 1);
  }
};

// Zero-area or non-finite triangles can never be hit; leaving them out of the tree
// guarantees that even when rounding would make their projected determinant nonzero.
bool degenerate(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(a[k]) || !std::isfinite(b[k]) || !std::isfinite(c[k])) return true;
  glm::dvec3 n = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
  return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

// Collapses the binary tree into 4-wide nodes: a node's children are its binary
// children, then the largest-area interior child is replaced by its two children until
// there are four (the greedy SAH-friendly collapse of Wald et al. 2008, "Getting Rid of
// Packets").
struct Collapser {
  const std::vector<BinNode>& bin;
  const std::vector<uint32_t>& refs;
  std::span<const glm::vec3> positions;
  std::vector<Bvh4Node>& out;
  std::vector<BvhTriBlock>& blocks;

  static float area(const BinNode& n) {
    glm::vec3 e(n.hi[0] - n.lo[0], n.hi[1] - n.lo[1], n.hi[2] - n.lo[2]);
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }

  uint32_t leaf(const BinNode& n) {
    BvhTriBlock b;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (uint32_t j = 0; j < 4; ++j) {
      bool used = j < n.count();
      uint32_t t = used ? refs[n.first + j] : 0;
      glm::vec3 v[3];
      for (int k = 0; k < 3; ++k) v[k] = used ? positions[3 * t + size_t(k)] : glm::vec3(nan);
      b.v0x[j] = v[0].x, b.v0y[j] = v[0].y, b.v0z[j] = v[0].z;
      b.v1x[j] = v[1].x, b.v1y[j] = v[1].y, b.v1z[j] = v[1].z;
      b.v2x[j] = v[2].x, b.v2y[j] = v[2].y, b.v2z[j] = v[2].z;
      b.prim[j] = used ? int32_t(t) : -1;
    }
    blocks.push_back(b);
    return uint32_t(blocks.size() - 1) | Bvh4Node::kLeafBit;
  }

  // Emits the 4-wide node for binary node `index` (an interior node, or the root leaf).
  uint32_t emit(uint32_t index) {
    uint32_t slot = uint32_t(out.size());
    out.emplace_back();
    uint32_t kids[4];
    uint32_t count = 0;
    if (bin[index].leaf()) {
      kids[count++] = index;
    } else {
      kids[count++] = bin[index].first;
      kids[count++] = bin[index].first + 1;
      while (count < 4) {
        int pick = -1;
        float best = -1.0f;
        for (uint32_t i = 0; i < count; ++i)
          if (!bin[kids[i]].leaf() && area(bin[kids[i]]) > best) best = area(bin[kids[i]]), pick = int(i);
        if (pick < 0) break;
        uint32_t k = kids[pick];
        kids[pick] = bin[k].first;
        kids[count++] = bin[k].first + 1;
      }
    }
    Bvh4Node node{};
    for (uint32_t i = 0; i < 4; ++i) {
      const BinNode& c = bin[kids[i < count ? i : 0]];
      node.lo_x[i] = c.lo[0], node.lo_y[i] = c.lo[1], node.lo_z[i] = c.lo[2];
      node.hi_x[i] = c.hi[0], node.hi_y[i] = c.hi[1], node.hi_z[i] = c.hi[2];
    }
    node.count = count;
    for (uint32_t i = 0; i < count; ++i)
      node.child[i] = bin[kids[i]].leaf() ? leaf(bin[kids[i]]) : emit(kids[i]);
    out[slot] = node;
    return slot;
  }
};

}  // namespace

Bvh Bvh::build(std::span<const glm::vec3> positions, BvhBuildStats* stats) {
  auto start = std::chrono::steady_clock::now();
  Bvh bvh;
  bvh.triangle_count_ = positions.size() / 3;
  std::vector<BinNode> bin;
  Builder b;
  b.nodes = &bin;
  b.tri_box.resize(bvh.triangle_count_);
  b.centroid.resize(bvh.triangle_count_);
  for (size_t t = 0; t < bvh.triangle_count_; ++t) {
    glm::vec3 p0 = positions[3 * t], p1 = positions[3 * t + 1], p2 = positions[3 * t + 2];
    if (degenerate(p0, p1, p2)) continue;
    Box box;
    box.grow(p0), box.grow(p1), box.grow(p2);
    b.tri_box[t] = box;
    // (lo + hi) / 2 overflows to inf for coordinates near FLT_MAX; lo / 2 + hi / 2 does
    // not, but may round differently for subnormal coordinates. Use it only where the
    // first overflowed, so every other centroid (and so the tree) stays bit-identical.
    glm::vec3 c = (box.lo + box.hi) * 0.5f;
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(c[k])) c[k] = box.lo[k] * 0.5f + box.hi[k] * 0.5f;
    b.centroid[t] = c;
    b.refs.push_back(uint32_t(t));
  }
  if (!b.refs.empty()) {
    bin.reserve(2 * b.refs.size());
    bin.resize(1);
    b.build(0, 0, uint32_t(b.refs.size()), 0);
    // Expected cost (MacDonald & Booth 1990): area-weighted node and triangle counts.
    double root_area = std::max(double(Collapser::area(bin[0])), 1e-30), cost = 0.0;
    for (const BinNode& node : bin)
      cost += double(Collapser::area(node)) / root_area * (node.leaf() ? double(node.count()) : 1.0);
    b.stats.sah_cost = cost;
    bvh.nodes_.reserve(bin.size() / 2 + 1);
    bvh.triangles_.reserve(b.stats.leaf_count);
    Collapser{bin, b.refs, positions, bvh.nodes_, bvh.triangles_}.emit(0);
  }
  b.stats.node_count = bvh.nodes_.size();
  b.stats.leaf_count = bvh.triangles_.size();
  b.stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = b.stats;
  return bvh;
}

size_t Bvh::triangle_count() const { return triangle_count_; }

}  // namespace zz
