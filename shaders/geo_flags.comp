#version 450
// Geometric discontinuity flags (ALGORITHM.md §7). A pixel is flagged when two
// 4-adjacent supersamples, at least one of them inside the pixel (the others form the
// ring), differ by: background vs geometry; with the material rule on, materials, for
// pairs of samples both inside the pixel (a material boundary that crosses the pixel's
// border separates its corners, which level 1 compares anyway; the rule is for what lies
// between them: a checker square's tip, a sliver); camera-facing geometric normals more than
// the angle threshold apart; or distances more than the relative threshold apart, where
// both triangles' planes are intersected exactly with the SAME sample ray, so surfaces
// that meet along an edge (smooth or coplanar tessellation) compare equal however
// grazing the view. The flag byte also says which way the edge runs (ZZ_GEO_ALONG_X: more
// of the differing pairs are vertical neighbours) and which zones it meets in that frame
// (visibility_shared.h). tests/gpu/flag_reference.h mirrors this rule bit for bit, and
// host/gpu/geo_flags_cpu.cpp implements it again with SSE.
//
// Shaped for lavapipe (8-wide SIMD on the CPU): an invocation flags the 4 pixels of one
// output word and reads the attachment directly (no copy), each sample row of their
// blocks once (4S + 2 ids, kept in registers: S is a specialisation constant, so the
// row loops unroll): (S + 2)(4S + 2)/4 = 27 loads per pixel at S = 4, where a loop per
// pixel over a copied buffer loaded 66. A shared-memory tile with an apron measured
// slower on lavapipe (process CPU 557 against 392 ms, room 1024^2 S = 4): its barriers
// run every group as coroutines. The per-triangle plane (normal,
// camera-relative offset) is one vec4 per id, computed per frame by triangle_planes.comp.
#extension GL_GOOGLE_include_directive : require
#include "visibility_shared.h"

layout(local_size_x = ZZ_FLAG_GROUP_X, local_size_y = ZZ_FLAG_GROUP_Y) in;
layout(constant_id = 0) const int S = 4;     // supersamples per pixel axis
const int P = ZZ_PIXELS_PER_WORD;             // pixels per invocation: one output word
const int ROW = P * S + 2;                   // samples per register row, ring included

layout(push_constant) uniform Push { FlagPush p; };
// The tile's id attachment (ring included), read directly: no copy into a buffer.
layout(binding = ZZ_BIND_IDS, r32ui) uniform readonly uimage2D ids;
layout(std430, binding = ZZ_BIND_PLANES) readonly buffer Planes { vec4 planes[]; };
layout(std430, binding = ZZ_BIND_NORMALS) readonly buffer Normals { vec4 normals[]; };  // w: material tag
layout(std430, binding = ZZ_BIND_FLAGS) writeonly buffer Flags { uint words[]; };


// An orthographic camera (limits.w = 1) steps its rays' origins by du, dv instead: every
// ray runs along dir00, from origin + gx du + gy dv. A specialisation constant (host: set
// with limits.w) rather than a branch on limits.w: lavapipe kept the orthographic code in
// the pinhole's flag pass, 12-22 % slower (glass, car 1024^2).
layout(constant_id = 1) const bool ORTHOGRAPHIC = false;
bool orthographic() { return ORTHOGRAPHIC; }

precise vec3 grid_step(ivec2 g) {
  precise vec3 d = float(g.x) * p.du.xyz;
  d = d + float(g.y) * p.dv.xyz;
  return d;
}

precise vec3 ray_dir(ivec2 g) {
  if (orthographic()) return p.dir00.xyz;
  precise vec3 d = p.dir00.xyz + float(g.x) * p.du.xyz;
  d = d + float(g.y) * p.dv.xyz;
  return d;
}

precise float dot3(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y;
  r = r + a.z * b.z;
  return r;
}

// !(|a - b| <= rel * min(a, b)) also flags NaN, infinities and planes behind the camera.
// An orthographic view looks the same from anywhere along its axis, so its depths are not
// relative to the distance from its plane but to the view's height (du.w).
bool far_apart(float a, float b) {
  precise float diff = abs(a - b);
  precise float lim = p.limits.y * (orthographic() ? p.du.w : min(a, b));
  return !(diff <= lim);
}

// `inner`: both samples inside the pixel, where the material rule applies.
bool differs(uint ia, ivec2 ga, uint ib, ivec2 gb, bool inner) {
  if (ia == ib) return false;
  if (ia == 0u || ib == 0u) return true;
  if (inner && p.limits.z != 0.0 && normals[ia - 1u].w != normals[ib - 1u].w) return true;
  vec4 pa = planes[ia - 1u];
  vec4 pb = planes[ib - 1u];
  vec3 na = pa.xyz, nb = pb.xyz;
  vec3 da = ray_dir(ga);
  vec3 db = ray_dir(gb);
  precise float sa = dot3(na, da);
  precise float sb = dot3(nb, db);
  // Orient both normals towards the camera: mesh winding need not be consistent.
  precise float c = dot3(na, nb);
  if ((sa < 0.0) != (sb < 0.0)) c = -c;
  if (c < p.limits.x) return true;
  // Plane n.x = n.v0 hit by ray o + t d at t = n.(v0 - o) / n.d; h = n.(v0 - o) per frame,
  // o the camera's origin; an orthographic ray's own origin lies grid_step further.
  precise float ha = pa.w, hb = pb.w;
  precise float hab = ha, hba = hb;  // sample b's offset for plane a, sample a's for plane b
  if (orthographic()) {
    precise vec3 oa = grid_step(ga), ob = grid_step(gb);
    hab = ha - dot3(na, ob);
    hba = hb - dot3(nb, oa);
    ha = ha - dot3(na, oa);
    hb = hb - dot3(nb, ob);
  }
  precise float taa = ha / sa;
  precise float tba = hba / dot3(nb, da);
  precise float tab = hab / dot3(na, db);
  precise float tbb = hb / sb;
  return far_apart(taa, tba) || far_apart(tbb, tab);
}

uint id_at(ivec2 u) { return imageLoad(ids, u).x; }

// The zone bit of canonical u, in units of 1 / (10 S) of a pixel (both neighbours on a zone
// boundary); host/core/geo_map.h's map_zone_at is the same function.
uint zone_at(int u) {
  int k = u / (2 * S);
  uint z = 1u << uint(min(k, 4));
  if (u % (2 * S) == 0 && k > 0 && k < 5) z |= 1u << uint(k - 1);
  return z;
}

// Flag bytes of the P pixels whose blocks (S x S core plus ring) start at image sample `c`;
// `g0` is the frame supersample of image sample (0, 0). lavapipe runs 8 invocations in
// SIMD and executes both sides of every branch under a mask, so the costly plane tests
// must not sit in a fixed loop over all pairs: each sample row (loaded once, kept in
// registers; S is a specialisation constant so these loops unroll) first collects the
// pairs of every pixel whose ids differ into bit masks, and only the set bits are
// visited. Every such pair is tested (no early exit on the first that differs): the
// counts of differing horizontal and vertical pairs say which way the edge runs.
uint word_flags(ivec2 c, ivec2 g0, int npix) {
  uint above[ROW];
  for (int i = 0; i < ROW; ++i) above[i] = id_at(c + ivec2(i, 0));
  int across[P], along[P];  // per pixel: differing horizontal pairs, differing vertical pairs
  uint zh[P], zv[P];        // per pixel: the zones they meet in the horizontal, vertical frame
  for (int k = 0; k < P; ++k) across[k] = along[k] = 0, zh[k] = zv[k] = 0u;
  for (int j = 1; j <= S + 1; ++j) {
    uint row[ROW];
    for (int i = 0; i < ROW; ++i) row[i] = id_at(c + ivec2(i, j));
    uint h[P], v[P];  // bit i of pixel k: pair at block column i (as in the single-pixel rule)
    for (int k = 0; k < P; ++k) {
      h[k] = 0u;
      v[k] = 0u;
      if (j <= S)
        for (int i = 0; i <= S; ++i) h[k] |= row[k * S + i] != row[k * S + i + 1] ? 1u << uint(i) : 0u;
      for (int i = 1; i <= S; ++i) v[k] |= row[k * S + i] != above[k * S + i] ? 1u << uint(i) : 0u;
    }
    for (int k = 0; k < npix; ++k) {
      uint hk = h[k], vk = v[k];
      ivec2 ck = c + ivec2(k * S, j);
      while (hk != 0u) {
        int i = findLSB(hk);
        hk &= hk - 1u;
        ivec2 a = ck + ivec2(i, 0), b = a + ivec2(1, 0);
        if (differs(id_at(a), a + g0, id_at(b), b + g0, i >= 1 && i < S)) {
          // Block column i is sample i - 1: the pair's midpoint at u = i / S; its row's
          // samples at y = (j - 0.5) / S, canonical u = 1 - y in the vertical frame.
          across[k] += 1;
          zh[k] |= zone_at(10 * i);
          zv[k] |= zone_at(10 * S - (10 * j - 5));
        }
      }
      while (vk != 0u) {
        int i = findLSB(vk);
        vk &= vk - 1u;
        ivec2 b = ck + ivec2(i, 0), a = b - ivec2(0, 1);
        if (differs(id_at(a), a + g0, id_at(b), b + g0, j >= 2 && j <= S)) {
          along[k] += 1;
          zh[k] |= zone_at(10 * i - 5);
          zv[k] |= zone_at(10 * S - 10 * (j - 1));
        }
      }
    }
    for (int i = 0; i < ROW; ++i) above[i] = row[i];
  }
  uint word = 0u;
  for (int k = 0; k < P; ++k) {
    uint f = across[k] + along[k] > 0 ? uint(ZZ_GEO_EDGE) : 0u;
    if (along[k] > across[k]) f |= uint(ZZ_GEO_ALONG_X) | zv[k] << uint(ZZ_GEO_ZONE_SHIFT);
    else f |= zh[k] << uint(ZZ_GEO_ZONE_SHIFT);
    word |= f << uint(8 * k);
  }
  return word;
}

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);  // word column, pixel row within the area
  ivec2 px = p.area.xy + ivec2(cell.x * P, cell.y);
  int npix = min(P, p.area.x + p.area.z - px.x);
  if (npix <= 0 || cell.y >= p.area.w) return;
  // Image sample u sits at frame supersample tile.x*S - 1 + u (the ring is u = 0).
  ivec2 c = (px - p.tile.xy) * S;
  ivec2 g0 = p.tile.xy * S - ivec2(1);
  words[(px.y - p.out_y0) * p.frame.w + (px.x - p.out_x0) / P] = word_flags(c, g0, npix);
}
