// The 25-point rank-1 lattice of a pixel and its roles (ALGORITHM.md §3, §6):
//   P_k = (k/25, (7k mod 25)/25), k = 0..24.
// Every column and row of step 0.04 holds one point; the set maps onto itself under
// 90 and 180 degree rotations. k = 0 is corner A. The fully refined "25 rays per pixel"
// pattern is these 25 points with the four corners weighing 1/4 each.
//
// "Canonical" k numbers the points in the horizontal frame (zones are strips along u).
// The vertical orientation rotates that frame 90° counter-clockwise: canonical (u, v)
// sits at physical (v, 1 - u), which is lattice point 7k mod 25 (7² ≡ -1 mod 25), so
// both orientations sample the very same physical points. Everything here is constexpr:
// one source of truth for positions, roles and interpolation weights.
#pragma once

#include <array>

namespace zz {

inline constexpr int kLatticePoints = 25;
inline constexpr int kZones = 5;

struct LatticePoint {
  float u, v;
};

constexpr LatticePoint lattice_point(int k) {
  return {float(k) / 25.0f, float((7 * k) % 25) / 25.0f};
}

constexpr std::array<LatticePoint, kLatticePoints> make_lattice() {
  std::array<LatticePoint, kLatticePoints> p{};
  for (int k = 0; k < kLatticePoints; ++k) p[k] = lattice_point(k);
  return p;
}

inline constexpr std::array<LatticePoint, kLatticePoints> kLattice = make_lattice();

// ---- roles (canonical k) -----------------------------------------------------
enum class Orientation : int { Horizontal = 0, Vertical = 1 };

inline constexpr int kE = 5, kG = 10, kF = 15, kH = 20;
// Level-2 packet lane order [E, F, G, H] (the order the masks of §5 are written in).
inline constexpr std::array<int, 4> kLevel2K = {kE, kF, kG, kH};
// Zone z holds canonical k = 5z+1 .. 5z+4 (one 4-ray zigzag packet).
constexpr int zone_k(int zone, int lane) { return 5 * zone + 1 + lane; }
// Zone of an inner canonical k that is not a level-2 point (-1 otherwise).
constexpr int zone_of(int k) { return (k % 5 == 0) ? -1 : k / 5; }

// Physical lattice index of canonical point k (k >= 1; k = 0 is the canonical corner A,
// which in the vertical frame is the physical bottom-left corner, see kCornerOfCanonical).
constexpr int physical_k(Orientation o, int k) {
  return o == Orientation::Horizontal ? k : (7 * k) % 25;
}
// Inverse: canonical k of physical point p (p >= 1). 18 = 7^-1 mod 25 (7 * 18 = 126).
constexpr int canonical_k(Orientation o, int p) {
  return o == Orientation::Horizontal ? p : (18 * p) % 25;
}

// Physical pixel corners are indexed TL=0, TR=1, BL=2, BR=3 (A, B, C, D of the
// horizontal frame). Canonical A, B, C, D in the vertical frame are the physical
// BL, TL, BR, TR (canonical (u, v) -> physical (v, 1 - u)).
inline constexpr int kCornerTL = 0, kCornerTR = 1, kCornerBL = 2, kCornerBR = 3;
inline constexpr int kCornerOfCanonical[2][4] = {{0, 1, 2, 3}, {2, 0, 3, 1}};

// Physical (x, y) offset inside the pixel of canonical point k in orientation o.
constexpr LatticePoint canonical_position(Orientation o, int k) {
  if (k == 0) {
    constexpr LatticePoint corner[4] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    return corner[kCornerOfCanonical[int(o)][0]];
  }
  return kLattice[physical_k(o, k)];
}

// ---- packet offset tables, per orientation (SoA, 16-byte aligned) ----------
struct alignas(16) PacketOffsets {
  float x[4];
  float y[4];
};

struct OrientationTables {
  PacketOffsets level2;          // lanes [E, F, G, H]
  PacketOffsets zone[kZones];    // lanes k = 5z+1 .. 5z+4
};

constexpr OrientationTables make_orientation_tables(Orientation o) {
  OrientationTables t{};
  for (int l = 0; l < 4; ++l) {
    LatticePoint p = canonical_position(o, kLevel2K[l]);
    t.level2.x[l] = p.u;
    t.level2.y[l] = p.v;
  }
  for (int z = 0; z < kZones; ++z)
    for (int l = 0; l < 4; ++l) {
      LatticePoint p = canonical_position(o, zone_k(z, l));
      t.zone[z].x[l] = p.u;
      t.zone[z].y[l] = p.v;
    }
  return t;
}

inline constexpr OrientationTables kOrientationTables[2] = {
    make_orientation_tables(Orientation::Horizontal), make_orientation_tables(Orientation::Vertical)};

// ---- level-3 interpolation weights (§6) ------------------------------------
// An untraced zone is interpolated linearly along u between its own boundaries:
// z0 between the corner edge A–C (at the point's v) and E, z1 E–G, z2 G–F, z3 F–H,
// z4 between H and the edge B–D. t = (u - u_left) / 0.2 = lane+1 over 5.
// Sources are canonical labels; weights per lane. Unused third source has weight 0
// and is never read (zones 1..3 have two sources).
enum InterpSource : int { kSrcA, kSrcB, kSrcC, kSrcD, kSrcE, kSrcF, kSrcG, kSrcH };

struct alignas(16) ZoneInterp {
  int count;            // 2 or 3 sources
  int source[3];
  float weight[3][4];   // [source][lane]
};

constexpr ZoneInterp make_zone_interp(int z) {
  ZoneInterp w{};
  for (int l = 0; l < 4; ++l) {
    const double t = double(l + 1) / 5.0;
    const double v = double((7 * zone_k(z, l)) % 25) / 25.0;  // canonical v of the point
    switch (z) {
      case 0:  // (1-t)((1-v)A + vC) + tE
        w.count = 3;
        w.source[0] = kSrcA, w.source[1] = kSrcC, w.source[2] = kSrcE;
        w.weight[0][l] = float((1 - t) * (1 - v));
        w.weight[1][l] = float((1 - t) * v);
        w.weight[2][l] = float(t);
        break;
      case 4:  // (1-t)H + t((1-v)B + vD)
        w.count = 3;
        w.source[0] = kSrcH, w.source[1] = kSrcB, w.source[2] = kSrcD;
        w.weight[0][l] = float(1 - t);
        w.weight[1][l] = float(t * (1 - v));
        w.weight[2][l] = float(t * v);
        break;
      default: {
        constexpr int left[5] = {0, kSrcE, kSrcG, kSrcF, 0};
        constexpr int right[5] = {0, kSrcG, kSrcF, kSrcH, 0};
        w.count = 2;
        w.source[0] = left[z], w.source[1] = right[z], w.source[2] = left[z];
        w.weight[0][l] = float(1 - t);
        w.weight[1][l] = float(t);
        w.weight[2][l] = 0.0f;
      }
    }
  }
  return w;
}

inline constexpr ZoneInterp kZoneInterp[kZones] = {make_zone_interp(0), make_zone_interp(1),
                                                   make_zone_interp(2), make_zone_interp(3),
                                                   make_zone_interp(4)};

}  // namespace zz
