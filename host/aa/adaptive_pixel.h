// Levels 1–3 of one pixel (ALGORITHM.md §4–§6), as small inline steps that the tile
// sampler, the analytic harness and the table tuner all call. Colours of a pixel's
// corners are packed SoA in physical order TL, TR, BL, BR (A, B, C, D of the horizontal
// frame), their signatures (signature.h) likewise in one int4. Every comparison is one
// SSE op over 4 pairs -> 4-bit mask -> table: d(p, q) = rho(p, q) > eps or sig(p) != sig(q).
#pragma once

#include <algorithm>
#include <bit>

#include "aa/adaptive_settings.h"
#include "aa/case_table.h"
#include "aa/lattice.h"
#include "aa/sample_source.h"
#include "aa/signature.h"
#include "aa/table_set.h"
#include "core/color.h"
#include "core/simd.h"
#include "core/tonemap.h"

namespace zz {

// ---- SSE helpers -------------------------------------------------------------
template <int a, int b, int c, int d>
inline float4 shuffle4(float4 v) {
  return _mm_shuffle_ps(v, v, _MM_SHUFFLE(d, c, b, a));
}
template <int a, int b, int c, int d>
inline Rgb4 shuffle4(const Rgb4& v) {
  return {shuffle4<a, b, c, d>(v.r), shuffle4<a, b, c, d>(v.g), shuffle4<a, b, c, d>(v.b)};
}
template <int lane>
inline Rgb4 broadcast(const Rgb4& v) {
  return shuffle4<lane, lane, lane, lane>(v);
}

// 4 colours stored AoS as float4 (r, g, b, 0) <-> one SoA Rgb4.
inline Rgb4 soa_from_aos(float4 a, float4 b, float4 c, float4 d) {
  __m128 r0 = a, r1 = b, r2 = c, r3 = d;
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  return {r0, r1, r2};
}
inline void aos_from_soa(const Rgb4& s, float4& a, float4& b, float4& c, float4& d) {
  __m128 r0 = s.r, r1 = s.g, r2 = s.b, r3 = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  a = r0, b = r1, c = r2, d = r3;
}

// d(p, q) of §2 for 4 pairs at once: bit i set where max_rgb |p_i - q_i| > eps
// (inputs already tone mapped; a distance equal to eps is no discontinuity).
inline int differs4(const Rgb4& p, const Rgb4& q, float4 eps) {
  float4 d = max(max(abs(p.r - q.r), abs(p.g - q.g)), abs(p.b - q.b));
  return (d > eps).bits();
}

// d(p, q) with signatures (§11): colours or signatures differ, 4 pairs at once.
inline int discontinuous4(const Rgb4& p, int4 sp, const Rgb4& q, int4 sq, float4 eps) {
  return differs4(p, q, eps) | signatures_differ4(sp, sq);
}

// ---- level 1 (§4) -----------------------------------------------------------
// Mask a0=d(A,B) a1=d(C,D) a2=d(A,C) a3=d(B,D): pairs [A,C,A,B] vs [B,D,C,D].
inline int corner_mask(const Rgb4& display, int4 sig, float4 eps) {
  return discontinuous4(shuffle4<0, 2, 0, 1>(display), shuffle4<0, 2, 0, 1>(sig), shuffle4<1, 3, 2, 3>(display),
                        shuffle4<1, 3, 2, 3>(sig), eps);
}

// Physical TL, TR, BL, BR -> canonical A, B, C, D of orientation o (lattice.h).
inline Rgb4 canonical_corners(const Rgb4& physical, Orientation o) {
  mask4 vertical(o == Orientation::Vertical);
  return select(vertical, shuffle4<2, 0, 3, 1>(physical), physical);
}
inline int4 canonical_corners(int4 physical, Orientation o) {
  mask4 vertical(o == Orientation::Vertical);
  return select(vertical, shuffle4<2, 0, 3, 1>(physical), physical);
}

// ---- level 2 (§5) -----------------------------------------------------------
struct Level2 {
  Orientation orientation = Orientation::Horizontal;  // indexes tables: never left unset
  Rgb4 corners;  // linear, canonical lanes [A, B, C, D]
  Rgb4 efgh;     // linear, lanes [E, F, G, H]
  int b = 0, c0 = 0, c1 = 0;  // the three masks
  int4 corner_sig{0}, efgh_sig{0};  // signatures, canonical lanes [A, B, C, D] and [E, F, G, H]
};

// `corners_sig`: the corners' signatures, physical order like the colours.
template <SampleSource S>
inline Level2 trace_level2(S& source, float4 px, float4 py, Orientation o, const Rgb4& corners_linear,
                           const Rgb4& corners_display, int4 corners_sig, const ToneMap& tonemap, float4 eps) {
  const PacketOffsets& off = kOrientationTables[int(o)].level2;
  Level2 r;
  r.orientation = o;
  r.corners = canonical_corners(corners_linear, o);
  int4 s;
  r.efgh = sample4_signed(source, px + float4::load(off.x), py + float4::load(off.y), s);
  const Rgb4 d = tonemap.apply4(r.efgh);
  const Rgb4 k = canonical_corners(corners_display, o);
  const int4 ks = canonical_corners(corners_sig, o);
  r.b = discontinuous4(shuffle4<0, 1, 0, 2>(d), shuffle4<0, 1, 0, 2>(s), shuffle4<1, 3, 2, 3>(d),
                       shuffle4<1, 3, 2, 3>(s), eps);                                           // EF FH EG GH
  r.c0 = discontinuous4(shuffle4<0, 3, 0, 3>(k), shuffle4<0, 3, 0, 3>(ks), d, s, eps);          // AE DF AG DH
  r.c1 = discontinuous4(k, ks, shuffle4<1, 3, 0, 2>(d), shuffle4<1, 3, 0, 2>(s), eps);          // AF BH CE DG
  r.corner_sig = ks;
  r.efgh_sig = s;
  return r;
}

// ---- the rule: one decision for the sampler and the tuner (§4, §5, §9, §11) ----------
// So that the tuner (table_tuning.cpp) optimises exactly what the sampler ships.

// Level 1: a pixel goes on to level 2 when its corner mask (colours and signatures) is a
// case, when the visibility map flags it, or always with refine_all; the case orients it.
// Where the case leaves the orientation open (orientation_open: a corner cut off, or no
// case) the paper takes horizontal; a geo pixel whose edge runs along x (`geo_along_x`,
// the map's ZZ_GEO_ALONG_X) takes vertical instead, so that its zones run along the edge.
// A checker edge nearly parallel to a pixel's top side cuts corner A off with a sliver along
// the whole side: horizontal zones each hold a piece of it and are interpolated from E..H
// beyond it; in the vertical frame the sliver lies in the one zone at that side, which the
// tables trace.
struct Level1 {
  bool refine;
  Orientation orientation;
};
inline Level1 decide_level1(const Rgb4& corners_display, int4 corners_sig, float4 eps, bool geo, bool refine_all,
                            bool geo_along_x = false) {
  const int mask = corner_mask(corners_display, corners_sig, eps);
  const PixelCase pcase = kCaseTable[mask];
  const bool vertical = pcase == PixelCase::Vertical || (geo_along_x && orientation_open(mask));
  return {pcase != PixelCase::None || geo || refine_all, vertical ? Orientation::Vertical : Orientation::Horizontal};
}

// Level 2: the zones a level-2 pixel traces: the three tables OR-ed, the `hdr` zones
// (hdr_zones below, or 0), for a geo pixel under GeoPolicy::Split, and with
// `split_unflagged` for any other, the `split` zones (split_zones below), for a geo pixel
// the `map` zones (the zones the visibility map saw
// its edge meet, when its frame is the pixel's: GeoMap::zones; 0 otherwise), and every zone
// with refine_all or for a geo pixel under GeoPolicy::All or whose masks all stayed zero
// while the map names no zone. §5 traces all five there because the rays missed a thin
// feature whose place they cannot tell; the map's samples saw where it is.
// The zones holding physical lattice points p (bit p of `points`, as in a hidden-detail
// flag: aa/hidden_detail.h) in orientation o's frame; a point at corner A or among E..H
// is traced anyway and names no zone.
constexpr int zone_of_physical(Orientation o, int p) { return p >= 1 && p < kLatticePoints ? zone_of(canonical_k(o, p)) : -1; }
inline int zones_of_points(Orientation o, uint32_t points) {
  int zones = 0;
  for (int p = 1; p < kLatticePoints; ++p) {
    const int z = zone_of_physical(o, p);
    if (((points >> p) & 1u) && z >= 0) zones |= 1 << z;
  }
  return zones;
}

// ---- gaps between refined pixels (ours, beyond §5) -------------------------------
// An unrefined pixel whose four corners all see an image (a mirror's, a glass's, what lies
// behind a thin BLEND pane) between two pixels that refine, left and right or above and
// below, refines too (--fill-gaps): there the image varies faster than the corners'
// spacing, and a line thinner than a pixel may lie between all four of its corners, as
// the stems refracted through the vase's thick wall do (every other column of pixels at
// level 1 between columns at level 3). The neighbours' decisions are level 1's by their
// corners and the map (refined_around in adaptive_sampler.h).
inline bool fills_gap(bool left, bool right, bool above, bool below) {
  return (left && right) || (above && below);
}

// Whether a refined pixel traces its split zones (a geo one per its policy).
inline bool splits_zones(bool geo, GeoPolicy policy, bool split_unflagged) {
  return geo ? policy == GeoPolicy::Split : split_unflagged;
}
inline int decide_zones(const TableSet& t, int b, int c0, int c1, int hdr, int split, bool geo, GeoPolicy policy,
                        bool refine_all, int map = 0, bool split_unflagged = false) {
  const bool no_mask = (b | c0 | c1) == 0;
  const int geo_map = geo ? map : 0;
  const bool full = refine_all || (geo && (policy == GeoPolicy::All || (no_mask && geo_map == 0)));
  const int split_traced = splits_zones(geo, policy, split_unflagged) ? split : 0;
  return t.zones(b, c0, c1) | hdr | split_traced | geo_map | (-int(full) & kAllZones);
}

// ---- zones across a high dynamic range (ours, beyond §5–§6) ---------------------
// The tables judge display colours, where a corner on a light's reflection (radiance 50)
// and the wall beside it (0.2) differ no more than white and black do. An untraced zone
// then spreads that corner over four of the 25 points (with z0 untraced, A weighs 1.33/25
// of the pixel instead of its 1/100), and the box mean is a linear sum: at 1024², four
// room pixels so built held 51 % of its excess error. A zone whose interpolation sources
// (kZoneInterp) differ, in any channel, by more than kHdrSpan / exposure is traced: that
// is beyond the range where T (tonemap.h) is near linear, T(1) = 0.82, so edges within
// the display's range stay the tables' to decide.
inline constexpr float kHdrSpan = 1.0f;
inline int hdr_zones(const Level2& l2, float exposure) {
  alignas(16) float v[3][8];  // [channel][A B C D E F G H]
  l2.corners.r.store(v[0]), l2.corners.g.store(v[1]), l2.corners.b.store(v[2]);
  l2.efgh.r.store(v[0] + 4), l2.efgh.g.store(v[1] + 4), l2.efgh.b.store(v[2] + 4);
  const float limit = kHdrSpan / exposure;
  int zones = 0;
  for (int z = 0; z < kZones; ++z) {
    const ZoneInterp& w = kZoneInterp[z];
    bool wide = false;
    for (const float* c : v) {
      float lo = c[w.source[0]], hi = lo;
      for (int i = 1; i < w.count; ++i) lo = std::min(lo, c[w.source[i]]), hi = std::max(hi, c[w.source[i]]);
      wide |= hi - lo > limit;
    }
    zones |= int(wide) << z;
  }
  return zones;
}

// ---- zones between samples that saw different things (ours, beyond §9) ------------
// The tables place an edge from colour masks alone, as a straight line through the pixel.
// A checker square's edge nearly parallel to a pixel's side cuts one corner off with a
// sliver that runs along the whole side; E..H all lie beyond it, the tables trace the one
// zone at that corner, and the zones along the sliver are interpolated from samples on its
// far side (glass 1024²: the worst refined pixels, 10/255 off, traced 9 rays). Where the
// visibility map says an edge crosses the pixel, a zone whose interpolation sources
// (kZoneInterp) differ in signature straddles it: the zones to trace (GeoPolicy::Split).
inline int split_zones(const Level2& l2) {
  alignas(16) int32_t sig[8];  // A B C D E F G H, as kZoneInterp numbers its sources
  l2.corner_sig.store(sig);
  l2.efgh_sig.store(sig + 4);
  int zones = 0;
  for (int z = 0; z < kZones; ++z) {
    const ZoneInterp& w = kZoneInterp[z];
    bool differ = false;
    for (int i = 1; i < w.count; ++i) differ |= sig[w.source[i]] != sig[w.source[0]];
    zones |= int(differ) << z;
  }
  return zones;
}

// ---- level 3 (§6) -----------------------------------------------------------
// Fills the 25 canonical lattice values (AoS, linear): traced zones from one packet each,
// the others interpolated with the §6 weights. lattice[0] is canonical A.
template <SampleSource S>
inline void trace_level3(S& source, float4 px, float4 py, const Level2& l2, int zones, float4* lattice) {
  const OrientationTables& t = kOrientationTables[int(l2.orientation)];
  const Rgb4 src[8] = {broadcast<0>(l2.corners), broadcast<1>(l2.corners), broadcast<2>(l2.corners),
                       broadcast<3>(l2.corners), broadcast<0>(l2.efgh),    broadcast<1>(l2.efgh),
                       broadcast<2>(l2.efgh),    broadcast<3>(l2.efgh)};
  for (int z = 0; z < kZones; ++z) {
    Rgb4 v;
    if ((zones >> z) & 1) {
      v = source.sample4(px + float4::load(t.zone[z].x), py + float4::load(t.zone[z].y));
    } else {
      const ZoneInterp& w = kZoneInterp[z];
      v = src[w.source[0]] * float4::load(w.weight[0]) + src[w.source[1]] * float4::load(w.weight[1]);
      if (w.count == 3) v = v + src[w.source[2]] * float4::load(w.weight[2]);
    }
    aos_from_soa(v, lattice[5 * z + 1], lattice[5 * z + 2], lattice[5 * z + 3], lattice[5 * z + 4]);
  }
  float4 dummy;
  aos_from_soa(l2.efgh, lattice[kE], lattice[kF], lattice[kG], lattice[kH]);
  aos_from_soa(l2.corners, lattice[0], dummy, dummy, dummy);
}

// Rays of a pixel: its corner (1), E..H (4), 4 per traced zone.
inline int refined_rays(int zones) { return 5 + 4 * std::popcount(unsigned(zones)); }

// ---- unrefined pixels to second order (ours, beyond §8) -------------------------
// Whether the four corners f(-1), f(0), f(1), f(2) from `q` in steps of `step` (a row or a
// column through the pixel and its ring) are not one curve: their two second differences
// d1 = f(-1) - 2 f(0) + f(1) and d2 = f(0) - 2 f(1) + f(2) are equal for a quadratic and
// opposite (|d1 - d2| = |d1| + |d2|) for a step between any two of them. A step smaller than
// eps (the shadow of one of many lights, a faint crease) is not curvature: correcting for
// it drew lines of 1/255 errors along every faint shadow edge (room 1024²: mean FLIP 1.375x
// the lattice's with them, 1.084x without). The ratio halfway, 0.5, tells the two apart;
// `mean` scales a floor for the float noise of flat shading. Bits of the channels that bend.
inline int bent(const float4* q, int step, float4 mean) {
  const float4 a = q[-step], b = q[0], c = q[step], d = q[2 * step];
  const float4 d1 = (a - b) - (b - c), d2 = (b - c) - (c - d);
  return (abs(d1 - d2) > float4(0.5f) * (abs(d1) + abs(d2)) + float4(1e-7f) * mean).bits() & 0x7;
}

// The mean of a pixel's corners is the trapezoid rule: for a smooth f it exceeds the box
// integral by (f_xx + f_yy) / 12 (Euler-Maclaurin, h = 1 pixel). Under a close light that
// bias is the same sign over whole walls, one or two 1/255 steps where 25 samples have
// none, and most of what FLIP sees of level 1 (room 512²: 80 % of the excess FLIP in flat
// pixels, its error correlating 0.999 with the reference's Laplacian / 12). The second
// differences come from the corners one step beyond the pixel (the grid's ring), two per
// axis, each row's f(-1) - f(0) - f(1) + f(2) being the sum of two second differences.
// Where an outer corner differs from the pixel's corner next to it (rho > eps: an edge, not
// curvature), a row or column of four corners is not one curve (bent: a step under eps), or
// the correction would move the pixel by a quarter of its value or more, the pixel keeps
// the plain mean. `lin` and `disp` point at the pixel's
// top-left corner in a grid of row stride `stride`.
inline float4 curvature_corrected(float4 mean, const float4* lin, const float4* disp, int stride, float4 eps) {
  const int s = stride;
  const Rgb4 inner_h = soa_from_aos(disp[0], disp[s], disp[1], disp[s + 1]);
  const Rgb4 outer_h = soa_from_aos(disp[-1], disp[s - 1], disp[2], disp[s + 2]);
  const Rgb4 inner_v = soa_from_aos(disp[0], disp[1], disp[s], disp[s + 1]);
  const Rgb4 outer_v = soa_from_aos(disp[-s], disp[1 - s], disp[2 * s], disp[2 * s + 1]);
  if ((differs4(inner_h, outer_h, eps) | differs4(inner_v, outer_v, eps)) != 0) return mean;
  if (bent(lin, 1, mean) | bent(lin + s, 1, mean) | bent(lin, s, mean) | bent(lin + 1, s, mean)) return mean;
  const float4 rows = ((lin[-1] - lin[0]) - (lin[1] - lin[2])) + ((lin[s - 1] - lin[s]) - (lin[s + 1] - lin[s + 2]));
  const float4 cols = ((lin[-s] - lin[0]) - (lin[s] - lin[2 * s])) +
                      ((lin[1 - s] - lin[1]) - (lin[s + 1] - lin[2 * s + 1]));
  // Curvature moves a pixel by a small fraction of its value; a correction of a quarter or
  // more is HDR values that the display saturates (1e3 beside 1e9 both show white), not shading.
  const float4 correction = (rows + cols) * float4(1.0f / 48.0f);
  if (((abs(correction) > mean * float4(0.25f)) | isnan(correction)).bits() & 0x7) return mean;
  return max(mean - correction, float4(0.0f));
}

// ---- box filter (§8) -------------------------------------------------------
// Unrefined: the mean of the corners (physical order; the same expression everywhere).
inline float4 corner_mean(float4 tl, float4 tr, float4 bl, float4 br) {
  return (((tl + tr) + bl) + br) * float4(0.25f);
}
// Refined: (1/4 (A+B+C+D) + sum of the 24 inner points) / 25.
inline float4 box_lattice(float4 tl, float4 tr, float4 bl, float4 br, const float4* lattice) {
  float4 inner(0.0f);
  for (int k = 1; k < kLatticePoints; ++k) inner += lattice[k];
  return (corner_mean(tl, tr, bl, br) + inner) / float4(25.0f);
}

}  // namespace zz
