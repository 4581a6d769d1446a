// The paper's zone tables (ALGORITHM.md §5) and the table-set registry.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "aa/adaptive_pixel.h"
#include "aa/table_set.h"

namespace zz {
namespace {

// "z1 z2" -> bit set; "–" -> 0; "all" -> 31.
uint8_t parse_zones(const std::string& text) {
  if (text == "all") return kAllZones;
  uint8_t bits = 0;
  std::istringstream in(text);
  std::string z;
  while (in >> z)
    if (z.size() == 2 && z[0] == 'z') bits |= uint8_t(1u << (z[1] - '0'));
  return bits;
}

TEST(ZoneTables, PaperTablesVerbatim) {
  // Rows copied from ALGORITHM.md §5 (mask written bit3 bit2 bit1 bit0): b | c0 | c1.
  const char* rows[16][3] = {
      {"–", "–", "–"},
      {"z1 z2", "z0", "z1 z2"},
      {"z3", "z3", "z4"},
      {"z2 z3", "z0 z3", "z1 z2 z4"},
      {"z1", "z1", "z0"},
      {"z1", "z0", "z0"},
      {"z1 z2 z3", "z1 z3", "z0 z4"},
      {"z1 z2 z3", "z0 z3", "z0 z4"},
      {"z2 z3", "z4", "z2 z3"},
      {"z2", "z0 z4", "z2"},
      {"z3", "z4", "z4"},
      {"z1 z2 z3", "z0 z4", "z2 z4"},
      {"z1 z2", "z1 z4", "z0 z2 z3"},
      {"z1 z2", "z0 z4", "z0 z2"},
      {"z1 z2 z3", "z1 z4", "z0 z4"},
      {"all", "all", "all"},
  };
  const TableSet* paper = find_table_set("paper");
  ASSERT_NE(paper, nullptr);
  for (int m = 0; m < 16; ++m) {
    EXPECT_EQ(paper->b[m], parse_zones(rows[m][0])) << "b row " << m;
    EXPECT_EQ(paper->c0[m], parse_zones(rows[m][1])) << "c0 row " << m;
    EXPECT_EQ(paper->c1[m], parse_zones(rows[m][2])) << "c1 row " << m;
  }
}

TEST(ZoneTables, WorkedExampleOfTheSpec) {
  // d(E,F), d(E,G), !d(G,H), !d(F,H): b = 0101 -> z1; d(A,F) with !d(C,E): c1 = 0001 -> z1 z2.
  const TableSet& paper = *find_table_set("paper");
  EXPECT_EQ(paper.b[0b0101], 0b00010);
  EXPECT_EQ(paper.c1[0b0001], 0b00110);
  EXPECT_EQ(paper.zones(0b0101, 0, 0b0001), 0b00110);
}

TEST(ZoneTables, WorkedExampleThroughTheMaskCode) {
  // The same example as colours: E, G on one side of an edge with F, H, A, C, B, D on the
  // other except as required. Level 2 masks come from the same SSE code the sampler runs.
  // E=1, F=0, G=0, H=0 gives d(E,F), d(E,G), !d(F,H), !d(G,H) -> b = 0101.
  struct Src {
    Rgb4 sample4(float4, float4) { return {float4(1, 0, 0, 0), float4(1, 0, 0, 0), float4(1, 0, 0, 0)}; }
  } src;
  // Corners: A = 1 so d(A,F) and !d(A,E); C = 1 so !d(C,E); B = 0 (!d(B,H)); D = 0.
  const Rgb4 corners{float4(1, 0, 1, 0), float4(1, 0, 1, 0), float4(1, 0, 1, 0)};
  ToneMap tm;
  const Level2 l2 = trace_level2(src, float4(0.0f), float4(0.0f), Orientation::Horizontal, corners,
                                 tm.apply4(corners), int4(0), tm, float4(0.1f));
  EXPECT_EQ(l2.b, 0b0101);
  EXPECT_EQ(l2.c0, 0b0100);  // !d(A,E), !d(D,F), d(A,G), !d(D,H): A = 1, G = 0
  EXPECT_EQ(l2.c1, 0b0001);  // d(A,F), !d(B,H), !d(C,E), !d(D,G)

  // The same pixel in the vertical orientation: canonical A, B, C, D are the physical BL,
  // TL, BR, TR corners (lattice.h), so canonical A = 1, B = 0, C = 1, D = 0 is physical
  // TL = 0, TR = 0, BL = 1, BR = 1. Same canonical colours, same masks.
  const Rgb4 vcorners{float4(0, 0, 1, 1), float4(0, 0, 1, 1), float4(0, 0, 1, 1)};
  const Level2 v = trace_level2(src, float4(0.0f), float4(0.0f), Orientation::Vertical, vcorners,
                                tm.apply4(vcorners), int4(0), tm, float4(0.1f));
  EXPECT_EQ(v.orientation, Orientation::Vertical);
  alignas(16) float canon[4];
  v.corners.r.store(canon);
  EXPECT_EQ(canon[0], 1.0f);  // A
  EXPECT_EQ(canon[1], 0.0f);  // B
  EXPECT_EQ(canon[2], 1.0f);  // C
  EXPECT_EQ(canon[3], 0.0f);  // D
  EXPECT_EQ(v.b, 0b0101);
  EXPECT_EQ(v.c0, 0b0100);
  EXPECT_EQ(v.c1, 0b0001);
  // And the physical corners of the horizontal example, read in the vertical frame, are a
  // different pixel: canonical A = BL = 1, B = TL = 1, C = BR = 0, D = TR = 0.
  const Level2 w = trace_level2(src, float4(0.0f), float4(0.0f), Orientation::Vertical, corners,
                                tm.apply4(corners), int4(0), tm, float4(0.1f));
  EXPECT_EQ(w.b, 0b0101);
  EXPECT_EQ(w.c0, 0b0100);   // AE 0, DF 0, AG 1, DH 0
  EXPECT_EQ(w.c1, 0b0111);   // AF 1, BH 1, CE 1, DG 0
}

// Every lane of every level-2 mask on its own: one of the eight points A..H bright, the
// rest dark, so exactly the pairs that hold it differ. A swap of two lanes (DF and DH,
// say) moves a bit and fails here, where the worked example's zeros would not see it.
TEST(ZoneTables, EachMaskLaneComparesItsOwnPair) {
  enum { A, B, C, D, E, F, G, H };
  const int b_pairs[4][2] = {{E, F}, {F, H}, {E, G}, {G, H}};   // ALGORITHM.md §5
  const int c0_pairs[4][2] = {{A, E}, {D, F}, {A, G}, {D, H}};
  const int c1_pairs[4][2] = {{A, F}, {B, H}, {C, E}, {D, G}};
  for (int bright = A; bright <= H; ++bright) {
    float v[8] = {};
    v[bright] = 1.0f;
    struct Src {
      float4 level2;
      Rgb4 sample4(float4, float4) { return {level2, level2, level2}; }
    } src{float4(v[E], v[F], v[G], v[H])};
    const float4 abcd(v[A], v[B], v[C], v[D]);
    const Rgb4 corners{abcd, abcd, abcd};
    ToneMap tm;
    const Level2 l2 = trace_level2(src, float4(0.0f), float4(0.0f), Orientation::Horizontal, corners,
                                   tm.apply4(corners), int4(0), tm, float4(0.1f));
    auto expected = [&](const int (&pairs)[4][2]) {
      int m = 0;
      for (int k = 0; k < 4; ++k) m |= int(v[pairs[k][0]] != v[pairs[k][1]]) << k;
      return m;
    };
    EXPECT_EQ(l2.b, expected(b_pairs)) << "bright point " << "ABCDEFGH"[bright];
    EXPECT_EQ(l2.c0, expected(c0_pairs)) << "bright point " << "ABCDEFGH"[bright];
    EXPECT_EQ(l2.c1, expected(c1_pairs)) << "bright point " << "ABCDEFGH"[bright];
  }
}

TEST(ZoneTables, RegistryAndAllSet) {
  EXPECT_EQ(find_table_set("nope"), nullptr);
  const auto names = table_set_names();
  ASSERT_EQ(names.size(), 4u);
  EXPECT_EQ(names[0], "paper");
  EXPECT_EQ(names[1], "tuned");
  EXPECT_EQ(names[2], "tuned-hq");
  EXPECT_EQ(names[3], "all");
  const TableSet& all = *find_table_set("all");
  for (int m = 0; m < 16; ++m) EXPECT_EQ(all.zones(m, 0, 0), kAllZones);
  // Each of its three tables on its own too: the tuner (table_tuning.cpp) starts from a
  // set's tables one by one. Mutation testing: a c1 entry other than all zones changed no test.
  for (int m = 0; m < 16; ++m) {
    EXPECT_EQ(all.b[m], kAllZones) << m;
    EXPECT_EQ(all.c0[m], kAllZones) << m;
    EXPECT_EQ(all.c1[m], kAllZones) << m;
  }
  EXPECT_EQ(all.zones(0, 0, 0), kAllZones);  // every zone of every level-2 pixel
}

}  // namespace
}  // namespace zz
