// ALGORITHM.md §9, reproduced: over single straight edges (120 angles x 141 offsets) the
// paper's tables leave a zone that the edge splits untraced in about 26 % of the
// configurations. An independent implementation of the spec measured that number, so
// this checks the whole level 1–2 chain (corner case, orientation, masks, tables)
// against it; the tuned set must do better.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aa/adaptive_pixel.h"
#include "aa/table_tuning.h"

namespace zz {
namespace {

double missed_fraction(const TableSet& tables, int* configurations = nullptr) {
  const AdaptiveSettings s;
  int refined = 0, missed = 0;
  for (int ai = 0; ai < 120; ++ai)
    for (int oi = 0; oi < 141; ++oi) {
      const double a = 2.0 * std::numbers::pi * ai / 120.0;
      PixelPattern p;
      p.nx = float(std::cos(a)), p.ny = float(std::sin(a));
      p.c = float(0.5 * (p.nx + p.ny) + (oi - 70) * 0.01);
      const PatternRecord r = evaluate_pattern(p, s);
      if (!r.refined) continue;
      ++refined;
      const PixelPatternSource src{&p};
      const Rgb4 corners = src.sample4(float4(0, 1, 0, 1), float4(0, 0, 1, 1));
      const PixelCase c = kCaseTable[corner_mask(s.tonemap.apply4(corners), int4(0), float4(s.eps))];
      const Orientation o = c == PixelCase::Vertical ? Orientation::Vertical : Orientation::Horizontal;
      const int zones = tables.zones(r.b, r.c0, r.c1);
      bool miss = false;
      for (int z = 0; z < kZones; ++z) {
        if ((zones >> z) & 1) continue;
        int inside = 0;
        for (int l = 0; l < 4; ++l) {
          const LatticePoint q = canonical_position(o, zone_k(z, l));
          inside += p.eval(q.u, q.v) > 0.5f;
        }
        miss |= inside != 0 && inside != 4;  // the edge splits this untraced zone
      }
      missed += miss;
    }
  if (configurations) *configurations = refined;
  return double(missed) / refined;
}

TEST(PaperWeakness, ObliqueEdgesUnderFlaggedAsMeasuredInTheSpec) {
  int n = 0;
  const double paper = missed_fraction(*find_table_set("paper"), &n);
  EXPECT_NEAR(n, 15152, 400);    // the edges that cross the pixel and reach level 2
  EXPECT_NEAR(paper, 0.26, 0.02);  // measured here: 25.6 %
  EXPECT_LT(missed_fraction(*find_table_set("tuned")), paper * 0.8);
}

}  // namespace
}  // namespace zz
