// Bounding volume hierarchy over the scene's triangles: binned-SAH build, nodes laid
// out for SSE traversal, closest-hit and any-hit queries for single rays and 4-ray
// packets. Watertight ray/triangle test (Woop, Benthin & Wald 2013) everywhere.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "accel/bvh_node.h"
#include "accel/ray.h"
#include "core/simd.h"

namespace zz {

// The tree is built binary (binned SAH) and then collapsed into 4-wide nodes; depth and
// SAH cost describe the binary tree, node and leaf counts the 4-wide one.
struct BvhBuildStats {
  double build_seconds = 0.0;
  size_t node_count = 0;  // 4-wide interior nodes
  size_t leaf_count = 0;  // leaves (blocks of <= 4 triangles)
  size_t max_depth = 0;   // of the binary SAH tree (root = 0)
  double sah_cost = 0.0;  // of the binary tree: traversal step = 1, triangle test = 1
};

class Bvh {
 public:
  Bvh() = default;
  // positions: 3 per triangle (Scene::positions). Degenerate triangles are kept but
  // can never be hit. The BVH keeps its own copy of the triangle data.
  static Bvh build(std::span<const glm::vec3> positions, BvhBuildStats* stats = nullptr);

  // All queries: hits with 0 < t <= tmax. t = 0 never counts, and neither does a hit
  // whose t its float rounding bound does not prove positive, unless a double-precision
  // re-test does (watertight.h; not tried within one rounding step of the coordinates,
  // where a ray meets the surface it left); spawn secondary rays from
  // offset_ray_origin. Equal t
  // goes to the lower triangle index, so a packet lane and the same ray through
  // intersect1 give bit-identical t, u, v, prim. Rays with a NaN or
  // infinite origin/direction, a zero direction, or a NaN tmax never hit. Thread-safe
  // (const, no allocation).

  // Closest hit along each active lane's ray; misses (and inactive lanes) give
  // prim = -1, t = inf, u = v = 0. Packets whose lanes diverge (different direction
  // octants or > ~37 degrees apart) are traced lane by lane internally. Known limit: a
  // ray with an exactly zero direction component whose origin lies exactly on a box face
  // of that axis culls the box (1/0 is clamped to 1e30, so the face's distance is 0), and
  // misses an edge lying in that face that brute force would hit. Float range: a
  // direction shorter than ~1e-19 (|d|^2 underflows, under FTZ as the tiles run) or
  // coordinates relative to the origin beyond ~1e13 or below ~1e-13 (t's numerator goes
  // as their cube) never hit; brute force agrees. Coplanar overlapping triangles may
  // resolve differently between a packet lane and a single ray (the box test's margin
  // covers t's rounding only up to 2^-18 of t).
  void intersect4(const RayPacket4& rays, mask4 active, HitPacket4& hits) const;
  // Any hit: the active lanes whose rays are blocked (each lane stops at its first hit).
  mask4 occluded4(const RayPacket4& rays, mask4 active) const;

  // Single rays (incoherent secondary rays): the same answers as a packet lane.
  Hit intersect1(const Ray& ray) const;
  bool occluded1(const Ray& ray) const;

  size_t triangle_count() const;
  bool empty() const { return triangle_count() == 0; }

  using Node = Bvh4Node;
  using TriangleData = BvhTriBlock;

 private:
  std::vector<Node> nodes_;              // [0] = root; empty when nothing can be hit
  std::vector<TriangleData> triangles_;  // one block of <= 4 triangles per leaf
  size_t triangle_count_ = 0;            // input triangles, degenerate ones included
};

}  // namespace zz
