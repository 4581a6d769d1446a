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
layout(binding = 0, r32ui) uniform readonly uimage2D ids;
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

uint id_at(ivec2 uv) { return imageLoad(ids, uv).x; }

// Pixel (x, y) of the tile covers image samples [x*S + 1, x*S + S] per axis.
bool pixel_flag(ivec2 pix) {
  int s = p.frame.z;
  ivec2 base = pix * s;                                  // ring corner, image coords
  ivec2 to_global = p.tile.xy * s - ivec2(1);            // image -> frame supersample
  for (int j = 1; j <= s; ++j) {                         // horizontal pairs
    ivec2 a = base + ivec2(0, j);
    uint ia = id_at(a);
    for (int i = 0; i <= s; ++i) {
      ivec2 b = a + ivec2(1, 0);
      uint ib = id_at(b);
      if (differs(ia, a + to_global, ib, b + to_global)) return true;
      a = b;
      ia = ib;
    }
  }
  for (int i = 1; i <= s; ++i) {                         // vertical pairs
    ivec2 a = base + ivec2(i, 0);
    uint ia = id_at(a);
    for (int j = 0; j <= s; ++j) {
      ivec2 b = a + ivec2(0, 1);
      uint ib = id_at(b);
      if (differs(ia, a + to_global, ib, b + to_global)) return true;
      a = b;
      ia = ib;
    }
  }
  return false;
}

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  int words_per_row = (p.tile.z + ZZ_PIXELS_PER_WORD - 1) / ZZ_PIXELS_PER_WORD;
  if (cell.x >= words_per_row || cell.y >= p.tile.w) return;
  uint word = 0u;
  for (int k = 0; k < ZZ_PIXELS_PER_WORD; ++k) {
    ivec2 pix = ivec2(cell.x * ZZ_PIXELS_PER_WORD + k, cell.y);
    if (pix.x >= p.tile.z) break;
    if (pixel_flag(pix)) word |= 1u << (8 * k);
  }
  int row = p.tile.y + cell.y;
  int col = p.tile.x / ZZ_PIXELS_PER_WORD + cell.x;
  words[row * p.frame.w + col] = word;
}
