// The 25-point lattice and its roles in both orientations (ALGORITHM.md §3).
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "aa/lattice.h"

namespace zz {
namespace {

// Integer lattice coordinates (in 1/25) of physical point k, read from the table.
std::pair<int, int> cell(int k) {
  return {int(std::lround(kLattice[k].u * 25.0f)), int(std::lround(kLattice[k].v * 25.0f))};
}

TEST(Lattice, PointsAreTheRank1Lattice) {
  for (int k = 0; k < kLatticePoints; ++k) {
    EXPECT_EQ(kLattice[k].u, float(k) / 25.0f);
    EXPECT_EQ(kLattice[k].v, float((7 * k) % 25) / 25.0f);
  }
  EXPECT_EQ(kLattice[0].u, 0.0f);
  EXPECT_EQ(kLattice[0].v, 0.0f);
}

TEST(Lattice, TwentyFiveDistinctColumnsAndRows) {
  std::set<int> cols, rows;
  for (int k = 0; k < kLatticePoints; ++k) cols.insert(cell(k).first), rows.insert(cell(k).second);
  EXPECT_EQ(cols.size(), 25u);
  EXPECT_EQ(rows.size(), 25u);
}

TEST(Lattice, InvariantUnder90And180Degrees) {
  std::set<std::pair<int, int>> pts;
  for (int k = 0; k < kLatticePoints; ++k) pts.insert(cell(k));
  ASSERT_EQ(pts.size(), 25u);
  for (auto [a, b] : pts) {
    EXPECT_TRUE(pts.count({b, (25 - a) % 25})) << "90: " << a << "," << b;           // (u,v) -> (v, 1-u)
    EXPECT_TRUE(pts.count({(25 - a) % 25, (25 - b) % 25})) << "180: " << a << "," << b;
  }
  // The vertical orientation's map is that rotation: canonical k sits on physical_k's point.
  for (int k = 1; k < kLatticePoints; ++k) {
    const auto [a, b] = cell(k);
    EXPECT_EQ(cell(physical_k(Orientation::Vertical, k)), std::make_pair(b, (25 - a) % 25)) << k;
  }
}

TEST(Lattice, HorizontalRoles) {
  const Orientation h = Orientation::Horizontal;
  auto near = [](LatticePoint p, float u, float v) { return std::fabs(p.u - u) < 1e-6f && std::fabs(p.v - v) < 1e-6f; };
  EXPECT_TRUE(near(canonical_position(h, 0), 0.0f, 0.0f));
  EXPECT_TRUE(near(canonical_position(h, kE), 0.2f, 0.4f));
  EXPECT_TRUE(near(canonical_position(h, kG), 0.4f, 0.8f));
  EXPECT_TRUE(near(canonical_position(h, kF), 0.6f, 0.2f));
  EXPECT_TRUE(near(canonical_position(h, kH), 0.8f, 0.6f));
  // Zones are vertical strips: zone z holds 0.2 z < u < 0.2 (z+1), one point per lane.
  for (int z = 0; z < kZones; ++z)
    for (int l = 0; l < 4; ++l) {
      const float u = kOrientationTables[0].zone[z].x[l];
      EXPECT_GT(u, 0.2f * z);
      EXPECT_LT(u, 0.2f * (z + 1));
      EXPECT_EQ(u, canonical_position(h, zone_k(z, l)).u);
    }
  EXPECT_EQ(kOrientationTables[0].level2.x[0], kLattice[5].u);  // lanes [E, F, G, H]
  EXPECT_EQ(kOrientationTables[0].level2.x[1], kLattice[15].u);
  EXPECT_EQ(kOrientationTables[0].level2.x[2], kLattice[10].u);
  EXPECT_EQ(kOrientationTables[0].level2.x[3], kLattice[20].u);
}

TEST(Lattice, VerticalIsTheRotatedFrame) {
  const Orientation v = Orientation::Vertical;
  // Canonical (u, v) sits at physical (v, 1 - u) — exactly a lattice point.
  for (int k = 1; k < kLatticePoints; ++k) {
    const LatticePoint c = kLattice[k], p = canonical_position(v, k);
    EXPECT_NEAR(p.u, c.v, 1e-6f) << k;
    EXPECT_NEAR(p.v, 1.0f - c.u, 1e-6f) << k;
    EXPECT_EQ(canonical_k(v, physical_k(v, k)), k);
  }
  // Canonical A, B, C, D are the physical bottom-left, top-left, bottom-right, top-right.
  EXPECT_EQ(kCornerOfCanonical[1][0], kCornerBL);
  EXPECT_EQ(kCornerOfCanonical[1][1], kCornerTL);
  EXPECT_EQ(kCornerOfCanonical[1][2], kCornerBR);
  EXPECT_EQ(kCornerOfCanonical[1][3], kCornerTR);
  EXPECT_EQ(canonical_position(v, 0).u, 0.0f);
  EXPECT_EQ(canonical_position(v, 0).v, 1.0f);
  // Zones become horizontal strips: zone z at 1 - 0.2 (z+1) < y < 1 - 0.2 z.
  for (int z = 0; z < kZones; ++z)
    for (int l = 0; l < 4; ++l) {
      const float y = kOrientationTables[1].zone[z].y[l];
      EXPECT_GT(y, 1.0f - 0.2f * (z + 1) - 1e-6f);
      EXPECT_LT(y, 1.0f - 0.2f * z + 1e-6f);
    }
  // The level-2 points are physically the same four points in both orientations.
  std::set<std::pair<float, float>> h2, v2;
  for (int l = 0; l < 4; ++l) {
    h2.insert({kOrientationTables[0].level2.x[l], kOrientationTables[0].level2.y[l]});
    v2.insert({kOrientationTables[1].level2.x[l], kOrientationTables[1].level2.y[l]});
  }
  EXPECT_EQ(h2, v2);
  // And every inner point is used exactly once per orientation.
  for (int o = 0; o < 2; ++o) {
    std::set<int> used;
    for (int k = 1; k < kLatticePoints; ++k) used.insert(physical_k(Orientation(o), k));
    EXPECT_EQ(used.size(), 24u);
    EXPECT_EQ(used.count(0), 0u);
  }
}

}  // namespace
}  // namespace zz
