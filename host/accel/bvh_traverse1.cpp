// Single-ray traversal for incoherent rays (Embree-style BVH4: Wald, Benthin & Boulos
// 2008, "Getting Rid of Packets"): one SSE slab test covers a node's four children, one
// SSE watertight test covers a leaf's four triangles, children are visited nearest first.
#include <cstddef>
#include <limits>

#include "accel/box_test.h"
#include "accel/bvh.h"
#include "accel/watertight.h"

namespace zz {
namespace {

constexpr float kFloatMax = std::numeric_limits<float>::max();

struct SingleSetup {
  float4 ox, oy, oz;     // origin, broadcast
  float origin[3];
  float4 rdx, rdy, rdz;  // safe reciprocal direction, broadcast
  watertight::RayShear shear;
  watertight::SpawnReach<float4> reach;  // broadcast
  float best;
  // Byte offsets of the near and far planes per axis inside Bvh4Node (lo_* or hi_*, by
  // the direction's sign): the slab test then needs no min/max per plane pair.
  int near_x, near_y, near_z, far_x, far_y, far_z;
};

inline float4 plane(const Bvh4Node& n, int offset) {
  return float4::load(reinterpret_cast<const float*>(reinterpret_cast<const char*>(&n) + offset));
}

// KX, KY, KZ: Woop's axis permutation as template arguments, so the leaf test picks
// registers instead of indexing memory.
template <bool kAnyHit, int kx, int ky, int kz>
bool traverse(const std::vector<Bvh4Node>& nodes, const std::vector<BvhTriBlock>& blocks,
              SingleSetup& s, Hit* out) {
  const float4 sx(s.shear.sx), sy(s.shear.sy), sz(s.shear.sz);
  int32_t best_prim = std::numeric_limits<int32_t>::max();
  float best_u = 0.0f, best_v = 0.0f;

  struct Entry {
    uint32_t ref;
    float tnear;
  } stack[kBvhStackSize];
  int sp = 0;
  uint32_t ref = 0;
  while (true) {
    if (!(ref & Bvh4Node::kLeafBit)) {
      const Bvh4Node& n = nodes[ref];
      // Slab test of the four children at once (conservative: see box_test.h).
      float4 t0x = (plane(n, s.near_x) - s.ox) * s.rdx, t1x = (plane(n, s.far_x) - s.ox) * s.rdx;
      float4 t0y = (plane(n, s.near_y) - s.oy) * s.rdy, t1y = (plane(n, s.far_y) - s.oy) * s.rdy;
      float4 t0z = (plane(n, s.near_z) - s.oz) * s.rdz, t1z = (plane(n, s.far_z) - s.oz) * s.rdz;
      float4 tnear = max(max(t0x, t0y), max(t0z, float4(0.0f)));
      float4 tfar = min(min(t1x, t1y), min(t1z, float4(s.best)));
      unsigned hit = unsigned((tnear <= tfar * kBoxFarScale).bits()) & ((1u << n.count) - 1u);
      if (hit) {
        int i0 = __builtin_ctz(hit);
        hit &= hit - 1;
        if (!hit) {  // the common case: a single child
          ref = n.child[i0];
          continue;
        }
        alignas(16) float tn[4];
        tnear.store(tn);
        if constexpr (kAnyHit) {  // any hit will do: no ordering work
          ref = n.child[i0];
          for (; hit; hit &= hit - 1) {
            int i = __builtin_ctz(hit);
            stack[sp++] = Entry{n.child[i], tn[i]};
          }
          continue;
        }
        int i1 = __builtin_ctz(hit);
        if (!(hit & (hit - 1))) {  // two children: push the farther, visit the nearer
          bool swap = tn[i1] < tn[i0];
          int near = swap ? i1 : i0, far = swap ? i0 : i1;
          stack[sp++] = Entry{n.child[far], tn[far]};
          ref = n.child[near];
          continue;
        }
        // Three or four: sort farthest first; push all but the nearest, visit it next.
        Entry e[4];
        int m = 0;
        e[m++] = Entry{n.child[i0], tn[i0]};
        for (; hit; hit &= hit - 1) {
          int i = __builtin_ctz(hit);
          Entry x{n.child[i], tn[i]};
          int j = m++;
          while (j > 0 && e[j - 1].tnear < x.tnear) e[j] = e[j - 1], --j;
          e[j] = x;
        }
        for (int j = 0; j < m - 1; ++j) stack[sp++] = e[j];
        ref = e[m - 1].ref;
        continue;
      }
    } else {
      const BvhTriBlock& b = blocks[ref & ~Bvh4Node::kLeafBit];
      // One ray against four triangles: per lane the same operations as a packet lane.
      float4 a[3] = {float4::load(b.v0x) - s.ox, float4::load(b.v0y) - s.oy, float4::load(b.v0z) - s.oz};
      float4 bb[3] = {float4::load(b.v1x) - s.ox, float4::load(b.v1y) - s.oy, float4::load(b.v1z) - s.oz};
      float4 c[3] = {float4::load(b.v2x) - s.ox, float4::load(b.v2y) - s.oy, float4::load(b.v2z) - s.oz};
      auto h = watertight::intersect<float4>(a[kx], a[ky], a[kz], bb[kx], bb[ky], bb[kz], c[kx],
                                             c[ky], c[kz], sx, sy, sz, s.reach);
      watertight::settle_uncertain(h, [&](int i) {
        const float p0[3] = {b.v0x[i], b.v0y[i], b.v0z[i]}, p1[3] = {b.v1x[i], b.v1y[i], b.v1z[i]},
                    p2[3] = {b.v2x[i], b.v2y[i], b.v2z[i]};
        return watertight::exact_intersect(p0, p1, p2, s.origin, kx, ky, kz, s.shear.sx, s.shear.sy, s.shear.sz);
      });
      unsigned hit = unsigned((h.hit & (h.t <= float4(s.best))).bits());
      if (hit) {
        if constexpr (kAnyHit) {
          return true;
        } else {
          alignas(16) float t[4], u[4], v[4];
          h.t.store(t), h.u.store(u), h.v.store(v);
          for (; hit; hit &= hit - 1) {
            int i = __builtin_ctz(hit);
            // Same tie-break as the packets: equal t goes to the lower original index.
            if (t[i] < s.best || (t[i] == s.best && b.prim[i] < best_prim)) {
              s.best = t[i];
              best_u = u[i], best_v = v[i], best_prim = b.prim[i];
            }
          }
        }
      }
    }
    // Pop the next subtree that may still hold a hit before the current tmax.
    while (true) {
      if (sp == 0) {
        if constexpr (!kAnyHit) {
          if (best_prim != std::numeric_limits<int32_t>::max())
            *out = Hit{s.best, best_u, best_v, best_prim};
        }
        return false;
      }
      --sp;
      if (stack[sp].tnear <= s.best * kBoxFarScale) {
        ref = stack[sp].ref;
        break;
      }
    }
  }
}

bool setup(const Ray& ray, SingleSetup& s) {
  s.shear = watertight::make_shear(ray.dir);
  if (!s.shear.valid || !std::isfinite(ray.origin.x) || !std::isfinite(ray.origin.y) ||
      !std::isfinite(ray.origin.z) || std::isnan(ray.tmax))
    return false;
  s.ox = float4(ray.origin.x), s.oy = float4(ray.origin.y), s.oz = float4(ray.origin.z);
  s.origin[0] = ray.origin.x, s.origin[1] = ray.origin.y, s.origin[2] = ray.origin.z;
  const watertight::SpawnReach<float> reach =
      watertight::spawn_reach(ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z);
  s.reach = {float4(reach.origin), float4(reach.per_unit)};
  s.rdx = float4(safe_rcp(ray.dir.x)), s.rdy = float4(safe_rcp(ray.dir.y));
  s.rdz = float4(safe_rcp(ray.dir.z));
  // FLT_MAX, not inf: a t that overflowed to inf must never count as a hit.
  s.best = std::min(ray.tmax, kFloatMax);
  constexpr int kLo = int(offsetof(Bvh4Node, lo_x)), kHi = int(offsetof(Bvh4Node, hi_x));
  constexpr int kRow = 4 * int(sizeof(float));
  int near[3], far[3];
  for (int k = 0; k < 3; ++k) {
    bool neg = !(ray.dir[k] >= 0.0f) || std::signbit(ray.dir[k]);  // -0 behaves like < 0
    near[k] = (neg ? kHi : kLo) + k * kRow;
    far[k] = (neg ? kLo : kHi) + k * kRow;
  }
  s.near_x = near[0], s.near_y = near[1], s.near_z = near[2];
  s.far_x = far[0], s.far_y = far[1], s.far_z = far[2];
  return s.best >= 0.0f;
}

template <bool kAnyHit>
bool dispatch(const std::vector<Bvh4Node>& nodes, const std::vector<BvhTriBlock>& blocks,
              SingleSetup& s, Hit* out) {
  return watertight::with_axis_permutation(s.shear.kx, s.shear.kz, [&]<int kX, int kY, int kZ>() {
    return traverse<kAnyHit, kX, kY, kZ>(nodes, blocks, s, out);
  });
}

}  // namespace

Hit Bvh::intersect1(const Ray& ray) const {
  Hit hit;
  SingleSetup s;
  if (nodes_.empty() || !setup(ray, s)) return hit;
  dispatch<false>(nodes_, triangles_, s, &hit);
  return hit;
}

bool Bvh::occluded1(const Ray& ray) const {
  SingleSetup s;
  if (nodes_.empty() || !setup(ray, s)) return false;
  return dispatch<true>(nodes_, triangles_, s, nullptr);
}

}  // namespace zz
