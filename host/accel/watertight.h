// Watertight ray/triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013), written once as a template over the lane type:
// F = float for single rays, F = float4 for 4-ray packets. Both instantiations execute
// the same IEEE operations in the same order (no FMA: -ffp-contract=off), so a lane of a
// packet and the single ray it came from produce bit-identical t, u, v.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "accel/ray.h"
#include "core/simd.h"

namespace zz::watertight {

// Scalar counterparts of the float4 helpers so the template reads the same for both.
inline bool any(bool m) { return m; }
inline float select(bool m, float a, float b) { return m ? a : b; }
inline bool lane(bool m, int) { return m; }
inline bool lane(mask4 m, int i) { return m[i]; }
inline bool any(mask4 m) { return m.any(); }
inline float get(float f, int) { return f; }
inline float get(float4 f, int i) { return f[i]; }
inline float abs(float f) { return std::fabs(f); }
inline float max(float a, float b) { return a > b ? a : b; }
inline float sqrt(float f) { return std::sqrt(f); }
inline void set(float& f, int, float x) { f = x; }
inline void set(float4& f, int i, float x) {
  alignas(16) float a[4];
  f.store(a);
  a[i] = x;
  f = float4::load(a);
}

// Per-ray constants of the paper's Section 3 (Figure 1, first block): kz is the
// dimension where |dir| is largest, kx/ky the other two, swapped when dir[kz] < 0 to
// keep the triangle's winding; S shears the ray onto +z with unit length.
struct RayShear {
  int kx, ky, kz;
  float sx, sy, sz;
  bool valid;  // false for NaN/inf/zero directions: such rays never hit
};

inline RayShear make_shear(glm::vec3 d) {
  RayShear s{};
  float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  s.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  s.kx = s.kz == 2 ? 0 : s.kz + 1;
  s.ky = s.kx == 2 ? 0 : s.kx + 1;
  if (d[s.kz] < 0.0f) std::swap(s.kx, s.ky);
  s.sx = d[s.kx] / d[s.kz];
  s.sy = d[s.ky] / d[s.kz];
  s.sz = 1.0f / d[s.kz];
  // A NaN component fails every comparison above, so test the results, not d.
  s.valid = std::isfinite(s.sx) && std::isfinite(s.sy) && std::isfinite(s.sz) &&
            std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
  return s;
}

// Calls f.template operator()<kx, ky, kz>() with the ray's axis permutation as compile-time
// constants: the six permutations of (kx, ky, kz), told apart by kz and whether kx follows
// kz cyclically (ky then follows kx, or the two were swapped for a negative dir[kz]).
template <class F>
decltype(auto) with_axis_permutation(int kx, int kz, F&& f) {
  switch (kz * 2 + (kx == (kz + 1) % 3 ? 0 : 1)) {
    case 0: return f.template operator()<1, 2, 0>();
    case 1: return f.template operator()<2, 1, 0>();
    case 2: return f.template operator()<2, 0, 1>();
    case 3: return f.template operator()<0, 2, 1>();
    case 4: return f.template operator()<0, 1, 2>();
    default: return f.template operator()<1, 0, 2>();
  }
}

// The paper's double-precision fallback (Section 3, "if U, V or W is exactly 0"): products
// of two floats are exact in double, so the sign of the 2x2 determinant is exact too.
inline void edges_double(float ax, float ay, float bx, float by, float cx, float cy, float& u,
                         float& v, float& w) {
  u = float(double(cx) * double(by) - double(cy) * double(bx));
  v = float(double(ax) * double(cy) - double(ay) * double(cx));
  w = float(double(bx) * double(ay) - double(by) * double(ax));
}

template <class F>
struct Result {
  decltype(F() < F()) hit;
  F t, u, v;  // u, v: barycentrics of vertices 1 and 2
  // Hits whose float t its bound does not prove positive, beyond the spawn reach's
  // rounding step: settle them with exact_intersect (intersect's end).
  decltype(F() < F()) uncertain;
};

// A hit whose t its rounding bound does not prove positive is refused if its t interval
// stays within 1/256 of this reach: one rounding step, gamma(8), of the largest coordinate
// of the origin and the triangle's vertices, in units of |d|. There a hit may be the
// surface the ray was spawned from, which the rounding cannot tell from a real one;
// beyond, the double-precision test decides (a ray grazing a plane at 1e-6 radians, whose
// t is uncertain by more than t itself, still hits it). Per ray: `origin` = 256 gamma(8)
// max|o_i| / |d| and `per_unit` = 256 gamma(8) / |d|, to which intersect adds the vertices' part.
inline constexpr float kSpawnReach = 256.0f * gamma(8);
template <class F>
struct SpawnReach {
  F origin, per_unit;
};
template <class F>
inline SpawnReach<F> spawn_reach(F ox, F oy, F oz, F dx, F dy, F dz) {
  const F per_unit = F(kSpawnReach) / sqrt(dx * dx + dy * dy + dz * dz);
  return {max(max(abs(ox), abs(oy)), abs(oz)) * per_unit, per_unit};
}

// The triangle's vertices relative to the ray origin, already permuted: a* = A[kx],
// A[ky], A[kz] and so on. sx, sy, sz from RayShear; `reach` from spawn_reach. Returns the
// hit mask for t above its rounding bound on a non-degenerate, not-missed triangle (so
// t = 0 is always refused), and the lanes in doubt for exact_intersect to settle; the
// caller compares t against its tmax.
template <class F>
inline Result<F> intersect(F akx, F aky, F akz, F bkx, F bky, F bkz, F ckx, F cky, F ckz, F sx,
                           F sy, F sz, SpawnReach<F> reach) {
  // Shear and scale the vertices into ray space (Eq. 1 of the paper, x and y only).
  F ax = akx - sx * akz, ay = aky - sy * akz;
  F bx = bkx - sx * bkz, by = bky - sy * bkz;
  F cx = ckx - sx * ckz, cy = cky - sy * ckz;
  // Scaled barycentrics: 2D edge functions of the ray (the origin of ray space).
  F u = cx * by - cy * bx;
  F v = ax * cy - ay * cx;
  F w = bx * ay - by * ax;
  F zero(0.0f);
  auto on_edge = (u == zero) | (v == zero) | (w == zero);
  if (any(on_edge)) {
    // Rare (rays through edges/vertices): redo those lanes exactly enough in double.
    for (int i = 0; i < int(sizeof(F) / sizeof(float)); ++i) {
      if (!lane(on_edge, i)) continue;
      float uu, vv, ww;
      edges_double(get(ax, i), get(ay, i), get(bx, i), get(by, i), get(cx, i), get(cy, i), uu, vv,
                   ww);
      set(u, i, uu);
      set(v, i, vv);
      set(w, i, ww);
    }
  }
  auto negative = (u < zero) | (v < zero) | (w < zero);
  auto positive = (u > zero) | (v > zero) | (w > zero);
  F det = u + v + w;
  // Outside when the signs are mixed; det == 0 means a degenerate projection. det is
  // tested with ordered comparisons, false for NaN: the padded slots of a leaf block have
  // NaN vertices, and `det != 0` (true for NaN) kept them from taking the early exit below.
  auto mixed = negative & positive;
  Result<F> r;
  r.hit = (!mixed) & ((det > zero) | (det < zero));
  // Most tests end here (the ray misses the triangle): skip the division.
  if (!any(r.hit)) {
    r.t = r.u = r.v = zero;
    r.uncertain = r.hit;
    return r;
  }
  // Hit z of ray space, scaled by det (the paper's T; two-sided, no culling).
  F t_scaled = u * (sz * akz) + v * (sz * bkz) + w * (sz * ckz);
  F rcp = F(1.0f) / det;
  r.t = t_scaled * rcp;
  r.u = v * rcp;
  r.v = w * rcp;
  // t carries rounding error; a hit nearer than its bound may be the triangle the ray
  // left, met again through the rounding of its spawned origin: the error grows as L^2 / w
  // on a sliver L long and w wide, and mirror rays off ToyCar's chrome strips (1000:1)
  // met their own facet at t = 1e-8 and showed the car's black instead of the sky.
  // Offset origins (ray_offset.cpp) are built for a t known to be positive; the bound
  // follows pbrt-v4 6.8.4: the sheared coordinates' errors (translation and shear), then
  // the edge functions', then t = sum(e_i z_i) / det's.
  const F max_z = max(max(abs(sz * akz), abs(sz * bkz)), abs(sz * ckz));
  const F max_x = max(max(abs(ax), abs(bx)), abs(cx));
  const F max_y = max(max(abs(ay), abs(by)), abs(cy));
  const F delta_z = F(gamma(3)) * max_z;
  const F delta_x = F(gamma(5)) * (max_x + max_z);
  const F delta_y = F(gamma(5)) * (max_y + max_z);
  const F delta_e = F(2.0f) * (F(gamma(2)) * max_x * max_y + delta_y * max_x + delta_x * max_y);
  const F max_e = max(max(abs(u), abs(v)), abs(w));
  const F delta_t = F(3.0f) * (F(gamma(3)) * max_e * max_z + delta_e * max_z + delta_z * max_e) * abs(rcp);
  // The vertices' largest coordinate relative to the origin bounds their own (with the origin's).
  const F max_vertex = max(max(max(max(abs(akx), abs(aky)), abs(akz)), max(max(abs(bkx), abs(bky)), abs(bkz))),
                           max(max(abs(ckx), abs(cky)), abs(ckz)));
  const F near = reach.origin + reach.per_unit * max_vertex;
  // Proven: t exceeds its bound. In doubt: the float t may be off by its whole bound
  // (0.33 for a true 0.46 on a floor 1e6 across), so the double test settles every hit
  // whose interval [t - delta_t, t + delta_t] reaches beyond one rounding step of the
  // coordinates (near / 256). Nearer, interpolated hit points could not place the hit
  // anyway, and what lies there is mostly the surface the ray left, met again at t ~ 0.
  r.uncertain = r.hit & !(r.t > delta_t) & ((r.t + delta_t) * F(256.0f) > near);
  r.hit = r.hit & (r.t > delta_t);
  return r;
}

// gamma for doubles: n rounded double operations, eps = 2^-53.
constexpr double gamma_d(int n) {
  constexpr double eps = 0x1p-53;
  return (double(n) * eps) / (1.0 - double(n) * eps);
}

struct ExactHit {
  bool hit = false;
  float t = 0.0f, u = 0.0f, v = 0.0f;
};

// intersect's t again in double, from the float vertices and origin, for a hit whose
// float t lay within its rounding bound. The float translation v - o alone errs by half an
// ULP of the larger coordinate, so near a triangle 1e5 across a real hit at t = 0.3 and
// the spawning surface met again at t ~ 0 look alike in float; in double (v - o exact,
// each product within 2^-53) they do not. A surface a ray was spawned from lies behind the
// offset origin (ray_offset.cpp bounds the hit point's error), so its exact t is <= 0 and
// the bound refuses it; `near`'s spawn reach is not needed here. Same shear constants as
// the float test (same ray), the bound of pbrt-v4 6.8.4 with double gammas, two more for
// the translation and the float-to-double steps. Lanes of a packet and single rays call it
// with the same floats, so they agree bit for bit.
inline ExactHit exact_intersect(const float p0[3], const float p1[3], const float p2[3], const float o[3], int kx,
                                int ky, int kz, float sx, float sy, float sz) {
  double a[3], b[3], c[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = double(p0[i]) - double(o[i]);
    b[i] = double(p1[i]) - double(o[i]);
    c[i] = double(p2[i]) - double(o[i]);
  }
  const double Sx = sx, Sy = sy, Sz = sz;
  const double ax = a[kx] - Sx * a[kz], ay = a[ky] - Sy * a[kz];
  const double bx = b[kx] - Sx * b[kz], by = b[ky] - Sy * b[kz];
  const double cx = c[kx] - Sx * c[kz], cy = c[ky] - Sy * c[kz];
  const double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
  ExactHit e;
  // Inside or out stays the float test's call: its edge tests are watertight with the
  // neighbour's, and a double verdict here, next to the neighbour's float one, would
  // open a crack along the shared edge (a ray through a floor's diagonal fell through).
  const double det = u + v + w;
  if (!(det > 0.0 || det < 0.0)) return e;
  const double az = Sz * a[kz], bz = Sz * b[kz], cz = Sz * c[kz];
  const double rcp = 1.0 / det;
  const double t = (u * az + v * bz + w * cz) * rcp;
  const double max_z = std::max({std::fabs(az), std::fabs(bz), std::fabs(cz)});
  const double max_x = std::max({std::fabs(ax), std::fabs(bx), std::fabs(cx)});
  const double max_y = std::max({std::fabs(ay), std::fabs(by), std::fabs(cy)});
  const double delta_z = gamma_d(5) * max_z;
  const double delta_x = gamma_d(7) * (max_x + max_z);
  const double delta_y = gamma_d(7) * (max_y + max_z);
  const double delta_e = 2.0 * (gamma_d(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
  const double max_e = std::max({std::fabs(u), std::fabs(v), std::fabs(w)});
  const double delta_t = 3.0 * (gamma_d(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * std::fabs(rcp);
  if (!(t > delta_t)) return e;
  // Barycentrics of the point on the plane, an edge's sign lost to rounding set to 0.
  const double sign = det > 0.0 ? 1.0 : -1.0;
  const double bu = std::max(0.0, sign * u), bv = std::max(0.0, sign * v), bw = std::max(0.0, sign * w);
  const double sum = bu + bv + bw;
  e.t = float(t);
  e.u = sum > 0.0 ? float(bv / sum) : 0.0f;
  e.v = sum > 0.0 ? float(bw / sum) : 0.0f;
  e.hit = e.t > 0.0f && std::isfinite(e.t);
  return e;
}

// Settles the uncertain lanes of r: `lane_hit(i)` is exact_intersect for lane i. Out of
// line: a handful of lanes per frame take it, and the leaf loops keep their registers.
template <class LaneHit>
[[gnu::noinline, gnu::cold]] void settle_lanes(Result<float4>& r, int bits, LaneHit& lane_hit) {
  alignas(16) float t[4], u[4], v[4];
  r.t.store(t), r.u.store(u), r.v.store(v);
  bool hit[4];
  for (int i = 0; i < 4; ++i) {
    hit[i] = r.hit[i];
    if (!((bits >> i) & 1)) continue;
    const ExactHit e = lane_hit(i);
    if (!e.hit) continue;
    hit[i] = true, t[i] = e.t, u[i] = e.u, v[i] = e.v;
  }
  r.t = float4::load(t), r.u = float4::load(u), r.v = float4::load(v);
  r.hit = mask4(hit[0], hit[1], hit[2], hit[3]);
}
template <class LaneHit>
inline void settle_uncertain(Result<float>& r, LaneHit&& lane_hit) {
  if (!r.uncertain) return;
  if (const ExactHit e = lane_hit(0); e.hit) r.hit = true, r.t = e.t, r.u = e.u, r.v = e.v;
}
template <class LaneHit>
inline void settle_uncertain(Result<float4>& r, LaneHit&& lane_hit) {
  if (const int bits = r.uncertain.bits(); bits != 0) [[unlikely]]
    settle_lanes(r, bits, lane_hit);
}

}  // namespace zz::watertight
