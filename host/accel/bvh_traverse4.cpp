// 4-ray packet traversal (Wald, Slusallek, Benthin & Wagner, "Interactive Rendering with
// Coherent Ray Tracing", 2001) over the 4-wide tree: one SSE lane per ray, the packet
// enters a child when any active lane hits its box; hit children are visited in order of
// their nearest entry distance over the packet.
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
  watertight::SpawnReach<float4> reach;  // per lane
  float4 best;           // current tmax; -inf for inactive or finished lanes
  // Per-lane permutation as blend masks: k == 0 and k == 1 (else 2).
  mask4 kx0, kx1, ky0, ky1, kz0, kz1;
  int kx, ky, kz;        // the shared permutation when `uniform`
  bool uniform;
  mask4 valid;
};

// Woop's per-ray constants for four lanes at once: the same comparisons and divisions
// as watertight::make_shear, lane by lane (so Sx, Sy, Sz match the single-ray path bit
// for bit), with the axis permutation kept as blend masks.
PacketSetup setup(const RayPacket4& r, mask4 active) {
  PacketSetup p;
  float4 ax = abs(r.dx), ay = abs(r.dy), az = abs(r.dz);
  // kz = argmax |d| with make_shear's tie-breaks.
  mask4 x_gt_y = ax > ay;
  mask4 kz0 = x_gt_y & (ax > az);
  mask4 kz1 = andnot(x_gt_y, ay > az);
  mask4 kz2 = !(kz0 | kz1);  // NaN lanes end here, like make_shear
  // kx follows kz cyclically, ky follows kx: (kz, kx, ky) = (0,1,2), (1,2,0), (2,0,1).
  float4 dkz = select(kz0, r.dx, select(kz1, r.dy, r.dz));
  mask4 flip = dkz < float4(0.0f);  // swap kx, ky to keep the winding
  mask4 kx0 = kz2, kx1 = kz0, ky0 = kz1, ky1 = kz2;
  auto pick = [](mask4 m, mask4 a, mask4 b) { return mask4(_mm_blendv_ps(b, a, m)); };
  mask4 sx0 = pick(flip, ky0, kx0), sx1 = pick(flip, ky1, kx1);
  mask4 sy0 = pick(flip, kx0, ky0), sy1 = pick(flip, kx1, ky1);
  p.kx0 = sx0, p.kx1 = sx1, p.ky0 = sy0, p.ky1 = sy1, p.kz0 = kz0, p.kz1 = kz1;
  float4 dkx = select(sx0, r.dx, select(sx1, r.dy, r.dz));
  float4 dky = select(sy0, r.dx, select(sy1, r.dy, r.dz));
  p.sx = dkx / dkz;
  p.sy = dky / dkz;
  p.sz = float4(1.0f) / dkz;
  mask4 valid = active & isfinite(p.sx) & isfinite(p.sy) & isfinite(p.sz) & isfinite(r.dx) &
                isfinite(r.dy) & isfinite(r.dz) & isfinite(r.ox) & isfinite(r.oy) &
                isfinite(r.oz) & !isnan(r.tmax);
  p.valid = valid;
  int bits = valid.bits();
  if (!bits) return p;
  // Permutation code per lane: 0..5; uniform when all valid lanes agree.
  int code[4];
  int m0 = kz0.bits(), m1 = kz1.bits(), mf = flip.bits();
  for (int i = 0; i < 4; ++i) code[i] = ((m0 >> i & 1) ? 0 : (m1 >> i & 1) ? 2 : 4) + (mf >> i & 1);
  int first = __builtin_ctz(unsigned(bits));
  p.uniform = true;
  for (int i = first + 1; i < 4; ++i)
    if ((bits >> i & 1) && code[i] != code[first]) p.uniform = false;
  static constexpr int kPerm[6][3] = {{1, 2, 0}, {2, 1, 0}, {2, 0, 1}, {0, 2, 1}, {0, 1, 2}, {1, 0, 2}};
  p.kx = kPerm[code[first]][0], p.ky = kPerm[code[first]][1], p.kz = kPerm[code[first]][2];
  // Safe reciprocals for the slab test (box_test.h): tiny components become +-1e-30.
  auto safe = [](float4 d) {
    float4 tiny = _mm_or_ps(signmask(d), _mm_set1_ps(1e-30f));
    return float4(1.0f) / select(abs(d) < float4(1e-30f), tiny, d);
  };
  p.rdx = safe(r.dx), p.rdy = safe(r.dy), p.rdz = safe(r.dz);
  p.ox = r.ox, p.oy = r.oy, p.oz = r.oz;
  p.reach = watertight::spawn_reach(r.ox, r.oy, r.oz, r.dx, r.dy, r.dz);
  // FLT_MAX, not inf: a t that overflowed to inf must never count as a hit.
  p.best = select(valid, min(r.tmax, float4(kFloatMax)), float4(-kInfinity));
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

// Slab test of child i of a 4-wide node against the packet: lanes that hit, and their
// entry distance.
inline mask4 box4(const PacketSetup& p, const Bvh4Node& n, int i, float4 best, float4& tnear) {
  float4 t0x = (float4(n.lo_x[i]) - p.ox) * p.rdx, t1x = (float4(n.hi_x[i]) - p.ox) * p.rdx;
  float4 t0y = (float4(n.lo_y[i]) - p.oy) * p.rdy, t1y = (float4(n.hi_y[i]) - p.oy) * p.rdy;
  float4 t0z = (float4(n.lo_z[i]) - p.oz) * p.rdz, t1z = (float4(n.hi_z[i]) - p.oz) * p.rdz;
  tnear = max(max(min(t0x, t1x), min(t0y, t1y)), max(min(t0z, t1z), float4(0.0f)));
  float4 tfar = min(min(max(t0x, t1x), max(t0y, t1y)), min(max(t0z, t1z), best));
  return tnear <= tfar * kBoxFarScale;
}

struct StackEntry {
  float4 tnear;  // +inf in lanes that missed the box
  uint32_t ref;
  float key;     // nearest entry over the lanes: the visiting order
};

template <bool kAnyHit, int KX, int KY, int KZ>
mask4 traverse(const std::vector<Bvh4Node>& nodes, const std::vector<BvhTriBlock>& blocks,
               PacketSetup& p, HitPacket4* out) {
  float4 best_u(0.0f), best_v(0.0f);
  int4 best_prim(std::numeric_limits<int32_t>::max());
  mask4 occluded(false);
  const float4 inf(kInfinity), minus_inf(-kInfinity);
  using PX = Pick<KX>;
  using PY = Pick<KY>;
  using PZ = Pick<KZ>;

  StackEntry stack[kBvhStackSize];
  int sp = 0;
  uint32_t ref = 0;
  while (true) {
    if (!(ref & Bvh4Node::kLeafBit)) {
      const Bvh4Node& n = nodes[ref];
      StackEntry e[4];
      int m = 0;
      for (uint32_t i = 0; i < n.count; ++i) {
        float4 tn;
        mask4 hit = box4(p, n, int(i), p.best, tn);
        if (hit.none()) continue;
        if constexpr (kAnyHit) {
          // Any hit ends a lane wherever it is found: ordering does not pay (measured
          // +6% on shadow rays).
          e[m++] = StackEntry{select(hit, tn, inf), n.child[i], 0.0f};
          continue;
        }
        // Order the children by the nearest entry over the packet, farthest first.
        StackEntry x{select(hit, tn, inf), n.child[i], hmin(select(hit, tn, inf))};
        int j = m++;
        while (j > 0 && e[j - 1].key < x.key) e[j] = e[j - 1], --j;
        e[j] = x;
      }
      if (m > 0) {
        for (int j = 0; j < m - 1; ++j) stack[sp++] = e[j];
        ref = e[m - 1].ref;
        continue;
      }
    } else {
      const BvhTriBlock& b = blocks[ref & ~Bvh4Node::kLeafBit];
      for (int j = 0; j < 4 && b.prim[j] >= 0; ++j) {
        float4 ax = float4(b.v0x[j]) - p.ox, ay = float4(b.v0y[j]) - p.oy, az = float4(b.v0z[j]) - p.oz;
        float4 bx = float4(b.v1x[j]) - p.ox, by = float4(b.v1y[j]) - p.oy, bz = float4(b.v1z[j]) - p.oz;
        float4 cx = float4(b.v2x[j]) - p.ox, cy = float4(b.v2y[j]) - p.oy, cz = float4(b.v2z[j]) - p.oz;
        auto h = watertight::intersect<float4>(
            PX::get(ax, ay, az, p.kx0, p.kx1), PY::get(ax, ay, az, p.ky0, p.ky1),
            PZ::get(ax, ay, az, p.kz0, p.kz1), PX::get(bx, by, bz, p.kx0, p.kx1),
            PY::get(bx, by, bz, p.ky0, p.ky1), PZ::get(bx, by, bz, p.kz0, p.kz1),
            PX::get(cx, cy, cz, p.kx0, p.kx1), PY::get(cx, cy, cz, p.ky0, p.ky1),
            PZ::get(cx, cy, cz, p.kz0, p.kz1), p.sx, p.sy, p.sz, p.reach);
        watertight::settle_uncertain(h, [&](int i) {
          const float p0[3] = {b.v0x[j], b.v0y[j], b.v0z[j]}, p1[3] = {b.v1x[j], b.v1y[j], b.v1z[j]},
                      p2[3] = {b.v2x[j], b.v2y[j], b.v2z[j]}, o[3] = {p.ox[i], p.oy[i], p.oz[i]};
          auto axis = [i](mask4 is0, mask4 is1) { return is0[i] ? 0 : is1[i] ? 1 : 2; };
          return watertight::exact_intersect(p0, p1, p2, o, axis(p.kx0, p.kx1), axis(p.ky0, p.ky1),
                                             axis(p.kz0, p.kz1), p.sx[i], p.sy[i], p.sz[i]);
        });
        if constexpr (kAnyHit) {
          mask4 hit = h.hit & (h.t <= p.best);
          if (hit.any()) {
            occluded |= hit;
            p.best = select(hit, minus_inf, p.best);
            if (!(p.best > minus_inf).any()) goto done;
          }
        } else {
          int4 prim(b.prim[j]);
          // Closest hit; equal t goes to the lower original index, so the result does
          // not depend on the order in which the packet or a single ray visits leaves.
          mask4 lower(_mm_castsi128_ps(_mm_cmplt_epi32(prim, best_prim)));
          mask4 hit = h.hit & ((h.t < p.best) | ((h.t == p.best) & lower));
          if (hit.any()) {
            p.best = select(hit, h.t, p.best);
            best_u = select(hit, h.u, best_u);
            best_v = select(hit, h.v, best_v);
            best_prim = select(hit, prim, best_prim);
          }
        }
      }
    }
    // Pop the next subtree that some lane may still hit before its current tmax.
    while (true) {
      if (sp == 0) goto done;
      --sp;
      // Capped at FLT_MAX: a lane without a hit yet has best = FLT_MAX, whose scaled value
      // is inf, and lanes that missed the box store tnear = inf; uncapped, nothing was
      // culled while any lane had no hit (1-5 % more leaves visited).
      if ((stack[sp].tnear <= min(p.best * kBoxFarScale, float4(kFloatMax))).any()) {
        ref = stack[sp].ref;
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
mask4 dispatch(const std::vector<Bvh4Node>& nodes, const std::vector<BvhTriBlock>& tris,
               PacketSetup& p, HitPacket4* out) {
  if (!p.uniform) return traverse<kAnyHit, -1, -1, -1>(nodes, tris, p, out);
  // Coherent packets share one of Woop's axis permutations.
  return watertight::with_axis_permutation(p.kx, p.kz, [&]<int kX, int kY, int kZ>() {
    return traverse<kAnyHit, kX, kY, kZ>(nodes, tris, p, out);
  });
}

// Whether the active lanes travel together: one direction octant and directions within
// about 37 degrees of each other (cos > 0.8; measured on tools/bench_traversal's
// secondary rays, wider packets are faster traced as single rays). NaN lanes count as
// divergent, so the single-ray path rejects them.
bool coherent(const RayPacket4& r, mask4 active) {
  int bits = active.bits();
  int sx = _mm_movemask_ps(r.dx), sy = _mm_movemask_ps(r.dy), sz = _mm_movemask_ps(r.dz);
  auto uniform = [&](int m) { return (m & bits) == 0 || (m & bits) == bits; };
  if (!uniform(sx) || !uniform(sy) || !uniform(sz)) return false;
  // cos > 0.8 without square roots: dot > 0 and dot^2 > 0.64 |a|^2 |b|^2.
  int first = __builtin_ctz(unsigned(bits));
  float4 fx(r.dx[first]), fy(r.dy[first]), fz(r.dz[first]);
  float4 dot = r.dx * fx + r.dy * fy + r.dz * fz;
  float4 la = r.dx * r.dx + r.dy * r.dy + r.dz * r.dz, lb = fx * fx + fy * fy + fz * fz;
  mask4 close = (dot > float4(0.0f)) & (dot * dot > float4(0.64f) * la * lb);
  return (close.bits() & bits) == bits;
}

Ray lane_ray(const RayPacket4& r, int i) {
  return Ray{{r.ox[i], r.oy[i], r.oz[i]}, {r.dx[i], r.dy[i], r.dz[i]}, r.tmax[i]};
}

}  // namespace

void Bvh::intersect4(const RayPacket4& rays, mask4 active, HitPacket4& hits) const {
  hits.t = float4(kInfinity);
  hits.u = hits.v = float4(0.0f);
  hits.prim = int4(-1);
  if (nodes_.empty() || active.none()) return;
  if (coherent(rays, active)) {
    PacketSetup p = setup(rays, active);
    if (p.valid.any()) dispatch<false>(nodes_, triangles_, p, &hits);
    return;
  }
  // Divergent lanes share few nodes: trace them one by one (the results are the same bit
  // for bit, only faster).
  alignas(16) float t[4] = {kInfinity, kInfinity, kInfinity, kInfinity}, u[4] = {}, v[4] = {};
  alignas(16) int32_t prim[4] = {-1, -1, -1, -1};
  for (int i = 0; i < 4; ++i) {
    if (!active[i]) continue;
    Hit h = intersect1(lane_ray(rays, i));
    t[i] = h.t, u[i] = h.u, v[i] = h.v, prim[i] = h.prim;
  }
  hits.t = float4::load(t), hits.u = float4::load(u), hits.v = float4::load(v);
  hits.prim = _mm_load_si128(reinterpret_cast<const __m128i*>(prim));
}

mask4 Bvh::occluded4(const RayPacket4& rays, mask4 active) const {
  if (nodes_.empty() || active.none()) return mask4(false);
  if (coherent(rays, active)) {
    PacketSetup p = setup(rays, active);
    return p.valid.any() ? dispatch<true>(nodes_, triangles_, p, nullptr) : mask4(false);
  }
  bool b[4] = {};
  for (int i = 0; i < 4; ++i) b[i] = active[i] && occluded1(lane_ray(rays, i));
  return mask4(b[0], b[1], b[2], b[3]);
}

}  // namespace zz
