#version 450
// Geometric discontinuity flags (ALGORITHM.md §7). A pixel is flagged when two
// 4-adjacent supersamples, at least one of them inside the pixel (the others form the
// ring), differ by: background vs geometry; camera-facing geometric normals more than
// the angle threshold apart; or distances more than the relative threshold apart, where
// both triangles' planes are intersected exactly with the SAME sample ray, so surfaces
// that meet along an edge (smooth or coplanar tessellation) compare equal however
// grazing the view. tests/gpu/flag_reference.h mirrors this rule bit for bit.
#extension GL_GOOGLE_include_directive : require
#include "visibility_shared.h"

layout(local_size_x = ZZ_FLAG_GROUP_X, local_size_y = ZZ_FLAG_GROUP_Y) in;

layout(push_constant) uniform Push { FlagPush p; };
// The tile's id image (ring included, rows of tile.z*S + 2 ids), copied into a buffer.
layout(std430, binding = 0) readonly buffer Ids { uint ids[]; };
layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 2) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 3) writeonly buffer Flags { uint words[]; };

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
  vec3 na = normals[ia - 1u].xyz;
  vec3 nb = normals[ib - 1u].xyz;
  vec3 da = ray_dir(ga);
  vec3 db = ray_dir(gb);
  precise float sa = dot3(na, da);
  precise float sb = dot3(nb, db);
  // Orient both normals towards the camera: mesh winding need not be consistent.
  precise float c = dot3(na, nb);
  if ((sa < 0.0) != (sb < 0.0)) c = -c;
  if (c < p.limits.x) return true;
  // Plane n.x = n.v0 hit by ray o + t d at t = n.(v0 - o) / n.d (Moller & Trumbore style,
  // camera-relative so the subtraction is exact for nearby geometry).
  precise float ha = dot3(na, positions[3u * (ia - 1u)].xyz - p.origin.xyz);
  precise float hb = dot3(nb, positions[3u * (ib - 1u)].xyz - p.origin.xyz);
  precise float taa = ha / sa;
  precise float tba = hb / dot3(nb, da);
  precise float tab = ha / dot3(na, db);
  precise float tbb = hb / sb;
  return far_apart(taa, tba) || far_apart(tbb, tab);
}

uint id_at(ivec2 uv) { return ids[uv.y * (p.tile.z * p.frame.z + 2) + uv.x]; }

// Flag of the pixel whose block (S x S core plus ring) has its corner at image sample
// `base`. lavapipe runs 8 invocations in SIMD and executes both sides of every branch
// under a mask, so the costly plane tests must not sit in a fixed loop over all pairs:
// each row first collects the differing pairs into bit masks with cheap compares, and
// only the set bits are visited (a loop ends once no lane has bits left).
bool pixel_flag(ivec2 base) {
  int s = p.frame.z;
  ivec2 to_global = p.tile.xy * s - ivec2(1);  // image -> frame supersample
  for (int j = 0; j <= s + 1; ++j) {
    uint h = 0u;  // bit i: horizontal pair (i, i+1) differs in id
    uint v = 0u;  // bit i: vertical pair (i, j-1)-(i, j) differs in id
    uint left = id_at(base + ivec2(0, j));
    for (int i = 1; i <= s + 1; ++i) {
      uint id = id_at(base + ivec2(i, j));
      uint above = id_at(base + ivec2(i, max(j - 1, 0)));
      h |= id != left ? 1u << uint(i - 1) : 0u;
      v |= id != above ? 1u << uint(i) : 0u;
      left = id;
    }
    if (j < 1 || j > s) h = 0u;  // horizontal pairs only in core rows
    v &= ((1u << uint(s + 1)) - 1u) & ~1u;  // vertical pairs only in core columns 1..S
    while (h != 0u) {
      int i = findLSB(h);
      h &= h - 1u;
      ivec2 a = base + ivec2(i, j), b = a + ivec2(1, 0);
      if (differs(id_at(a), a + to_global, id_at(b), b + to_global)) return true;
    }
    while (v != 0u) {
      int i = findLSB(v);
      v &= v - 1u;
      ivec2 b = base + ivec2(i, j), a = b - ivec2(0, 1);
      if (differs(id_at(a), a + to_global, id_at(b), b + to_global)) return true;
    }
  }
  return false;
}

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  int s = p.frame.z;
  int npix = min(ZZ_PIXELS_PER_WORD, p.tile.z - cell.x * ZZ_PIXELS_PER_WORD);
  if (npix <= 0 || cell.y >= p.tile.w) return;
  uint word = 0u;
  for (int k = 0; k < npix; ++k) {
    ivec2 base = ivec2((cell.x * ZZ_PIXELS_PER_WORD + k) * s, cell.y * s);
    if (pixel_flag(base)) word |= 1u << uint(8 * k);
  }
  int row = p.tile.y + cell.y;
  int col = p.tile.x / ZZ_PIXELS_PER_WORD + cell.x;
  words[row * p.frame.w + col] = word;
}
