// 4-ray packet traversal (Wald, Slusallek, Benthin & Wagner, "Interactive Rendering with
// Coherent Ray Tracing", 2001): one SSE lane per ray, the packet descends a node when any
// active lane hits its box. Both children are tested from the parent; the near child is
// the one on the side the first active ray points to along the node's split axis.
#include <cstring>
#include <limits>

#include "accel/box_test.h"
#include "accel/bvh.h"
#include "accel/watertight.h"

namespace zz {
namespace {

constexpr float kFloatMax = std::numeric_limits<float>::max();

struct PacketSetup {
  float4 ox, oy, oz;
  float4 rdx, rdy, rdz;  // safe reciprocals for the slab test
  float4 sx, sy, sz;     // Woop shear, per lane
  float4 best;           // current tmax; -inf for inactive or finished lanes
  // Per-lane permutation as blend masks: k == 0 and k == 1 (else 2).
  mask4 kx0, kx1, ky0, ky1, kz0, kz1;
  int kx, ky, kz;        // the shared permutation when `uniform`
  bool uniform;
  int neg[3];            // direction signs of the first active lane (near/far order)
  mask4 valid;
};

PacketSetup setup(const RayPacket4& r, mask4 active) {
  PacketSetup p;
  alignas(16) float o[3][4], d[3][4], tmax[4], rd[3][4], s[3][4], best[4];
  alignas(16) int32_t k[3][4][2];
  r.ox.store(o[0]), r.oy.store(o[1]), r.oz.store(o[2]);
  r.dx.store(d[0]), r.dy.store(d[1]), r.dz.store(d[2]);
  r.tmax.store(tmax);
  int first = -1;
  p.uniform = true;
  bool valid[4];
  int perm[4][3];
  for (int i = 0; i < 4; ++i) {
    glm::vec3 dir(d[0][i], d[1][i], d[2][i]);
    watertight::RayShear sh = watertight::make_shear(dir);
    valid[i] = active[i] && sh.valid && std::isfinite(o[0][i]) && std::isfinite(o[1][i]) &&
               std::isfinite(o[2][i]) && !std::isnan(tmax[i]);
    perm[i][0] = sh.kx, perm[i][1] = sh.ky, perm[i][2] = sh.kz;
    s[0][i] = sh.sx, s[1][i] = sh.sy, s[2][i] = sh.sz;
    for (int a = 0; a < 3; ++a) rd[a][i] = safe_rcp(dir[a]);
    // FLT_MAX, not inf: a t that overflowed to inf must never count as a hit.
    best[i] = valid[i] ? std::min(tmax[i], kFloatMax) : -kInfinity;
    if (!valid[i]) continue;
    if (first < 0) {
      first = i;
      for (int a = 0; a < 3; ++a) p.neg[a] = dir[a] < 0.0f;
      p.kx = sh.kx, p.ky = sh.ky, p.kz = sh.kz;
    } else if (sh.kx != p.kx || sh.ky != p.ky || sh.kz != p.kz) {
      p.uniform = false;
    }
  }
  if (first < 0) {
    p.valid = mask4(false);
    return p;
  }
  for (int i = 0; i < 4; ++i) {
    if (!valid[i])  // inactive lanes follow the first lane: keeps `uniform` meaningful
      for (int a = 0; a < 3; ++a) perm[i][a] = perm[first][a];
    for (int a = 0; a < 3; ++a) {
      k[a][i][0] = perm[i][a] == 0 ? -1 : 0;
      k[a][i][1] = perm[i][a] == 1 ? -1 : 0;
    }
  }
  auto mask_of = [&](int a, int which) {
    return mask4(k[a][0][which] != 0, k[a][1][which] != 0, k[a][2][which] != 0,
                 k[a][3][which] != 0);
  };
  p.kx0 = mask_of(0, 0), p.kx1 = mask_of(0, 1);
  p.ky0 = mask_of(1, 0), p.ky1 = mask_of(1, 1);
  p.kz0 = mask_of(2, 0), p.kz1 = mask_of(2, 1);
  p.ox = r.ox, p.oy = r.oy, p.oz = r.oz;
  p.rdx = float4::load(rd[0]), p.rdy = float4::load(rd[1]), p.rdz = float4::load(rd[2]);
  p.sx = float4::load(s[0]), p.sy = float4::load(s[1]), p.sz = float4::load(s[2]);
  p.best = float4::load(best);
  p.valid = mask4(valid[0], valid[1], valid[2], valid[3]);
  return p;
}

// Component K of (x, y, z), K known at compile time; K < 0: per lane from the masks.
template <int K>
struct Pick {
  static float4 get(float4 x, float4 y, float4 z, mask4, mask4) {
    return K == 0 ? x : (K == 1 ? y : z);
  }
};
template <>
struct Pick<-1> {
  static float4 get(float4 x, float4 y, float4 z, mask4 is0, mask4 is1) {
    return select(is0, x, select(is1, y, z));
  }
};

// Slab test of one box against the packet: lanes that hit, and their entry distance.
inline mask4 box4(const PacketSetup& p, const BvhNode& n, float4 best, float4& tnear) {
  __m128 lo = _mm_load_ps(n.lo), hi = _mm_load_ps(n.hi);
  float4 t0x = (bcast<0>(lo) - p.ox) * p.rdx, t1x = (bcast<0>(hi) - p.ox) * p.rdx;
  float4 t0y = (bcast<1>(lo) - p.oy) * p.rdy, t1y = (bcast<1>(hi) - p.oy) * p.rdy;
  float4 t0z = (bcast<2>(lo) - p.oz) * p.rdz, t1z = (bcast<2>(hi) - p.oz) * p.rdz;
  tnear = max(max(min(t0x, t1x), min(t0y, t1y)), max(min(t0z, t1z), float4(0.0f)));
  float4 tfar = min(min(max(t0x, t1x), max(t0y, t1y)), min(max(t0z, t1z), best));
  return tnear <= tfar * kBoxFarScale;
}

struct StackEntry {
  float4 tnear;  // +inf in lanes that missed the box
  uint32_t node;
};

template <bool kAnyHit, int KX, int KY, int KZ>
mask4 traverse(const std::vector<BvhNode>& nodes, const std::vector<BvhTriangle>& tris,
               PacketSetup& p, HitPacket4* out) {
  float4 best_u(0.0f), best_v(0.0f);
  int4 best_prim(std::numeric_limits<int32_t>::max());
  mask4 occluded(false);
  const float4 inf(kInfinity), minus_inf(-kInfinity);

  StackEntry stack[kBvhMaxDepth + 1];
  int sp = 0;
  float4 tn;
  uint32_t node = 0;
  if (!box4(p, nodes[0], p.best, tn).any()) goto done;
  while (true) {
    {
      const BvhNode& n = nodes[node];
      if (!n.leaf()) {
        float4 tl, tr;
        mask4 ml = box4(p, nodes[n.first], p.best, tl);
        mask4 mr = box4(p, nodes[n.first + 1], p.best, tr);
        int hl = ml.bits(), hr = mr.bits();
        if (hl && hr) {
          bool right_first = p.neg[n.axis()];
          stack[sp].node = right_first ? n.first : n.first + 1;
          stack[sp].tnear = right_first ? select(ml, tl, inf) : select(mr, tr, inf);
          ++sp;
          node = right_first ? n.first + 1 : n.first;
          continue;
        }
        if (hl | hr) {
          node = hl ? n.first : n.first + 1;
          continue;
        }
      } else {
        const BvhTriangle* tri = &tris[n.first];
        const BvhTriangle* end = tri + n.count();
        for (; tri != end; ++tri) {
          __m128 r0 = _mm_load_ps(tri->v0), r1 = _mm_load_ps(tri->v1),
                 r2 = _mm_load_ps(tri->v2);
          float4 ax = bcast<0>(r0) - p.ox, ay = bcast<1>(r0) - p.oy, az = bcast<2>(r0) - p.oz;
          float4 bx = bcast<0>(r1) - p.ox, by = bcast<1>(r1) - p.oy, bz = bcast<2>(r1) - p.oz;
          float4 cx = bcast<0>(r2) - p.ox, cy = bcast<1>(r2) - p.oy, cz = bcast<2>(r2) - p.oz;
          using PX = Pick<KX>;
          using PY = Pick<KY>;
          using PZ = Pick<KZ>;
          auto h = watertight::intersect<float4>(
              PX::get(ax, ay, az, p.kx0, p.kx1), PY::get(ax, ay, az, p.ky0, p.ky1),
              PZ::get(ax, ay, az, p.kz0, p.kz1), PX::get(bx, by, bz, p.kx0, p.kx1),
              PY::get(bx, by, bz, p.ky0, p.ky1), PZ::get(bx, by, bz, p.kz0, p.kz1),
              PX::get(cx, cy, cz, p.kx0, p.kx1), PY::get(cx, cy, cz, p.ky0, p.ky1),
              PZ::get(cx, cy, cz, p.kz0, p.kz1), p.sx, p.sy, p.sz);
          if constexpr (kAnyHit) {
            mask4 hit = h.hit & (h.t <= p.best);
            if (hit.any()) {
              occluded |= hit;
              p.best = select(hit, minus_inf, p.best);
              if (!(p.best > minus_inf).any()) goto done;
            }
          } else {
            int4 prim(tri->prim);
            // Closest hit; equal t goes to the lower original index, so the result does
            // not depend on the order in which the packet or a single ray visits leaves.
            mask4 closer = (h.t < p.best) |
                           ((h.t == p.best) & mask4(_mm_castsi128_ps(_mm_cmplt_epi32(prim, best_prim))));
            mask4 hit = h.hit & closer;
            if (hit.any()) {
              p.best = select(hit, h.t, p.best);
              best_u = select(hit, h.u, best_u);
              best_v = select(hit, h.v, best_v);
              best_prim = select(hit, prim, best_prim);
            }
          }
        }
      }
    }
    // Pop the next subtree that some lane may still hit before its current tmax.
    while (true) {
      if (sp == 0) goto done;
      --sp;
      if ((stack[sp].tnear <= p.best * kBoxFarScale).any()) {
        node = stack[sp].node;
        break;
      }
    }
  }
done:
  if constexpr (!kAnyHit) {
    mask4 hit = !(best_prim == int4(std::numeric_limits<int32_t>::max()));
    out->t = select(hit, p.best, inf);
    out->u = select(hit, best_u, float4(0.0f));
    out->v = select(hit, best_v, float4(0.0f));
    out->prim = select(hit, best_prim, int4(-1));
  }
  return occluded;
}

template <bool kAnyHit>
mask4 dispatch(const std::vector<BvhNode>& nodes, const std::vector<BvhTriangle>& tris,
               PacketSetup& p, HitPacket4* out) {
  if (!p.uniform) return traverse<kAnyHit, -1, -1, -1>(nodes, tris, p, out);
  // The six axis permutations of Woop's (kx, ky, kz); coherent packets share one.
  switch (p.kz * 2 + (p.kx == (p.kz + 1) % 3 ? 0 : 1)) {
    case 0: return traverse<kAnyHit, 1, 2, 0>(nodes, tris, p, out);
    case 1: return traverse<kAnyHit, 2, 1, 0>(nodes, tris, p, out);
    case 2: return traverse<kAnyHit, 2, 0, 1>(nodes, tris, p, out);
    case 3: return traverse<kAnyHit, 0, 2, 1>(nodes, tris, p, out);
    case 4: return traverse<kAnyHit, 0, 1, 2>(nodes, tris, p, out);
    default: return traverse<kAnyHit, 1, 0, 2>(nodes, tris, p, out);
  }
}

}  // namespace

void Bvh::intersect4(const RayPacket4& rays, mask4 active, HitPacket4& hits) const {
  hits.t = float4(kInfinity);
  hits.u = hits.v = float4(0.0f);
  hits.prim = int4(-1);
  if (nodes_.empty() || active.none()) return;
  PacketSetup p = setup(rays, active);
  if (p.valid.none()) return;
  dispatch<false>(nodes_, triangles_, p, &hits);
}

mask4 Bvh::occluded4(const RayPacket4& rays, mask4 active) const {
  if (nodes_.empty() || active.none()) return mask4(false);
  PacketSetup p = setup(rays, active);
  if (p.valid.none()) return mask4(false);
  return dispatch<true>(nodes_, triangles_, p, nullptr);
}

}  // namespace zz
