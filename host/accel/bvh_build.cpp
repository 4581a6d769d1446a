// Binned SAH build (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", 2007): 32 centroid bins per axis, leaves chosen by the SAH itself.
// Single-threaded and free of unordered containers, so the tree is a pure function of
// the input.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "accel/bvh.h"

namespace zz {
namespace {

constexpr int kBins = 32;
constexpr uint32_t kMaxLeafSize = 8;
// SAH constants: cost of one traversal step relative to one triangle test. Measured
// (tools/bench_traversal): the packet triangle test costs about as much as two box
// tests, which favours leaves of 2-4 triangles.
constexpr float kTraversalCost = 1.0f;
constexpr float kTriangleCost = 1.0f;
// From this depth on, split by object median so the tree depth stays bounded.
constexpr int kMedianDepth = kBvhMaxDepth - 40;

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
  std::vector<BvhNode>* nodes;
  BvhBuildStats stats;

  void make_leaf(BvhNode& node, uint32_t begin, uint32_t end) {
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
      BvhNode& node = (*nodes)[index];
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
        float scale = float(kBins) * 0.99999f / extent[axis];
        for (uint32_t i = begin; i < end; ++i) {
          int b = std::min(kBins - 1, int((centroid[refs[i]][axis] - cbounds.lo[axis]) * scale));
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
    float leaf_cost = kTriangleCost * float(n);
    float split_cost = parent_area > 0.0f
                           ? kTraversalCost + kTriangleCost * best_cost / parent_area
                           : kTraversalCost + leaf_cost;
    if (n <= kMaxLeafSize && (best_axis < 0 || leaf_cost <= split_cost))
      return make_leaf((*nodes)[index], begin, end);

    uint32_t mid;
    int axis;
    if (best_axis >= 0) {
      axis = best_axis;
      float scale = float(kBins) * 0.99999f / extent[axis];
      float lo = cbounds.lo[axis];
      auto left_of = [&](uint32_t r) {
        return std::min(kBins - 1, int((centroid[r][axis] - lo) * scale)) <= best_bin;
      };
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

}  // namespace

Bvh Bvh::build(std::span<const glm::vec3> positions, BvhBuildStats* stats) {
  auto start = std::chrono::steady_clock::now();
  Bvh bvh;
  bvh.triangle_count_ = positions.size() / 3;
  Builder b;
  b.nodes = &bvh.nodes_;
  b.tri_box.resize(bvh.triangle_count_);
  b.centroid.resize(bvh.triangle_count_);
  for (size_t t = 0; t < bvh.triangle_count_; ++t) {
    glm::vec3 p0 = positions[3 * t], p1 = positions[3 * t + 1], p2 = positions[3 * t + 2];
    if (degenerate(p0, p1, p2)) continue;
    Box box;
    box.grow(p0), box.grow(p1), box.grow(p2);
    b.tri_box[t] = box;
    b.centroid[t] = (box.lo + box.hi) * 0.5f;
    b.refs.push_back(uint32_t(t));
  }
  if (!b.refs.empty()) {
    bvh.nodes_.reserve(2 * b.refs.size());
    bvh.nodes_.resize(1);
    b.build(0, 0, uint32_t(b.refs.size()), 0);
    bvh.triangles_.resize(b.refs.size());
    for (size_t i = 0; i < b.refs.size(); ++i) {
      uint32_t t = b.refs[i];
      BvhTriangle& d = bvh.triangles_[i];
      for (int k = 0; k < 3; ++k) {
        d.v0[k] = positions[3 * t][k];
        d.v1[k] = positions[3 * t + 1][k];
        d.v2[k] = positions[3 * t + 2][k];
      }
      d.prim = int32_t(t);
      d.pad1 = d.pad2 = 0.0f;
    }
    // Expected cost (MacDonald & Booth 1990): area-weighted node and triangle counts.
    double root_area = 0.0, cost = 0.0;
    for (const BvhNode& node : bvh.nodes_) {
      Box box;
      box.lo = {node.lo[0], node.lo[1], node.lo[2]};
      box.hi = {node.hi[0], node.hi[1], node.hi[2]};
      if (root_area == 0.0) root_area = std::max(double(box.area()), 1e-30);
      cost += double(box.area()) / root_area * (node.leaf() ? double(node.count()) : 1.0);
    }
    b.stats.sah_cost = cost;
  }
  b.stats.node_count = bvh.nodes_.size();
  b.stats.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = b.stats;
  return bvh;
}

size_t Bvh::triangle_count() const { return triangle_count_; }

}  // namespace zz
