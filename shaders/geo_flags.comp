#version 450
// Geometric discontinuity flags (ALGORITHM.md §7). A pixel is flagged when two
// 4-adjacent supersamples, at least one of them inside the pixel (the others form the
// ring), differ by: background vs geometry; camera-facing geometric normals more than
// the angle threshold apart; or distances more than the relative threshold apart, where
// both triangles' planes are intersected exactly with the SAME sample ray, so surfaces
// that meet along an edge (smooth or coplanar tessellation) compare equal however
// grazing the view. tests/gpu/flag_reference.h mirrors this rule bit for bit, and
// host/gpu/geo_flags_cpu.cpp implements it again with SSE.
//
// Shaped for lavapipe (8-wide SIMD on the CPU): a group flags TILE x TILE pixels; it
// loads their ids plus the one-sample apron into shared memory once (each id is read
// from the attachment once), every invocation keeps one row of its block in registers
// (S is a specialisation constant, so the row loops unroll), the per-triangle plane
// (normal, camera-relative offset) is one vec4 computed per frame by triangle_planes.comp,
// and the flags leave as one uint per 4 pixels.
#extension GL_GOOGLE_include_directive : require
#include "visibility_shared.h"

layout(local_size_x = ZZ_FLAG_GROUP_X, local_size_y = ZZ_FLAG_GROUP_Y) in;
layout(constant_id = 0) const int S = 4;     // supersamples per pixel axis
layout(constant_id = 1) const int TILE = 8;  // pixels per group side: 8 or 4 (shared memory)
const int SIDE = TILE * S + 2;               // shared tile side in samples, apron included
const int WORDS = TILE / ZZ_PIXELS_PER_WORD; // output words per group row

layout(push_constant) uniform Push { FlagPush p; };
// The tile's id attachment (ring included), read directly: no copy into a buffer.
layout(binding = ZZ_BIND_IDS, r32ui) uniform readonly uimage2D ids;
layout(std430, binding = ZZ_BIND_PLANES) readonly buffer Planes { vec4 planes[]; };
layout(std430, binding = ZZ_BIND_FLAGS) writeonly buffer Flags { uint words[]; };

shared uint tile_ids[SIDE * SIDE];
shared uint tile_words[TILE * WORDS];

precise vec3 ray_dir(ivec2 g) {
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
bool far_apart(float a, float b) {
  precise float diff = abs(a - b);
  precise float lim = p.limits.y * min(a, b);
  return !(diff <= lim);
}

bool differs(uint ia, ivec2 ga, uint ib, ivec2 gb) {
  if (ia == ib) return false;
  if (ia == 0u || ib == 0u) return true;
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
  // Plane n.x = n.v0 hit by ray o + t d at t = n.(v0 - o) / n.d; h = n.(v0 - o) per frame.
  precise float ha = pa.w;
  precise float hb = pb.w;
  precise float taa = ha / sa;
  precise float tba = hb / dot3(nb, da);
  precise float tab = ha / dot3(na, db);
  precise float tbb = hb / sb;
  return far_apart(taa, tba) || far_apart(tbb, tab);
}

uint shared_id(ivec2 t) { return tile_ids[t.y * SIDE + t.x]; }

// Flag of the pixel whose block (S x S core plus ring) has its corner at shared-tile
// sample `c`; `g0` is the frame supersample of shared sample (0, 0). lavapipe runs 8
// invocations in SIMD and executes both sides of every branch under a mask, so the
// costly plane tests must not sit in a fixed loop over all pairs: each row first
// collects the differing pairs into bit masks with cheap compares on ids kept in
// registers, and only the set bits are visited.
bool pixel_flag(ivec2 c, ivec2 g0) {
  uint above[S + 2];
  for (int i = 0; i <= S + 1; ++i) above[i] = shared_id(c + ivec2(i, 0));
  for (int j = 1; j <= S + 1; ++j) {
    uint row[S + 2];
    for (int i = 0; i <= S + 1; ++i) row[i] = shared_id(c + ivec2(i, j));
    uint h = 0u;  // bit i: horizontal pair (i, i+1) differs in id (core rows only)
    uint v = 0u;  // bit i: vertical pair (i, j-1)-(i, j) differs in id (core columns only)
    if (j <= S)
      for (int i = 0; i <= S; ++i) h |= row[i] != row[i + 1] ? 1u << uint(i) : 0u;
    for (int i = 1; i <= S; ++i) v |= row[i] != above[i] ? 1u << uint(i) : 0u;
    while (h != 0u) {
      int i = findLSB(h);
      h &= h - 1u;
      ivec2 a = c + ivec2(i, j), b = a + ivec2(1, 0);
      if (differs(shared_id(a), a + g0, shared_id(b), b + g0)) return true;
    }
    while (v != 0u) {
      int i = findLSB(v);
      v &= v - 1u;
      ivec2 b = c + ivec2(i, j), a = b - ivec2(0, 1);
      if (differs(shared_id(a), a + g0, shared_id(b), b + g0)) return true;
    }
    for (int i = 0; i <= S + 1; ++i) above[i] = row[i];
  }
  return false;
}

void main() {
  const uint invocations = ZZ_FLAG_GROUP_X * ZZ_FLAG_GROUP_Y;
  uint lid = gl_LocalInvocationIndex;
  ivec2 px0 = p.area.xy + ivec2(gl_WorkGroupID.xy) * TILE;  // frame pixel of the group's corner
  ivec2 area_end = p.area.xy + p.area.zw;
  // Image sample u sits at frame supersample tile.x*S - 1 + u (the ring is u = 0).
  ivec2 u0 = (px0 - p.tile.xy) * S;
  ivec2 u_last = (area_end - p.tile.xy) * S + 1;  // last sample the area's pixels read
  for (uint k = lid; k < uint(SIDE * SIDE); k += invocations) {
    ivec2 t = ivec2(int(k) % SIDE, int(k) / SIDE);
    tile_ids[k] = imageLoad(ids, min(u0 + t, u_last)).x;
  }
  if (lid < uint(TILE * WORDS)) tile_words[lid] = 0u;
  barrier();

  ivec2 g0 = px0 * S - ivec2(1);
  for (uint q = lid; q < uint(TILE * TILE); q += invocations) {
    ivec2 l = ivec2(int(q) % TILE, int(q) / TILE);
    ivec2 pixel = px0 + l;
    if (all(lessThan(pixel, area_end)) && pixel_flag(l * S, g0))
      atomicOr(tile_words[l.y * WORDS + l.x / ZZ_PIXELS_PER_WORD], 1u << uint(8 * (l.x % ZZ_PIXELS_PER_WORD)));
  }
  barrier();

  if (lid < uint(TILE * WORDS)) {
    ivec2 w = ivec2(int(lid) % WORDS, int(lid) / WORDS);
    ivec2 first = px0 + ivec2(w.x * ZZ_PIXELS_PER_WORD, w.y);  // the word's first pixel
    if (all(lessThan(first, area_end)))
      words[first.y * p.frame.w + first.x / ZZ_PIXELS_PER_WORD] = tile_words[lid];
  }
}
