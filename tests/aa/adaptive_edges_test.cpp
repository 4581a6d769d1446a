// Axis-aligned edges at each of the 25 lattice columns/rows (ALGORITHM.md §9): the zone
// holding the edge is always traced and the pixel equals the 25-point lattice result.
#include <gtest/gtest.h>

#include <cmath>

#include "test_sources.h"

namespace zz {
namespace {

void check_edges(const char* tables) {
  AdaptiveSettings s;
  s.tables = find_table_set(tables);
  AdaptiveSettings full = s;
  full.refine_all = true;
  constexpr int kSize = 6, kCol = 2;
  for (int vertical_line = 0; vertical_line < 2; ++vertical_line)
    for (int polarity = 0; polarity < 2; ++polarity)
      for (int c = 0; c < 25; ++c) {
        // Halfway between lattice columns c and c+1 of pixel column/row kCol.
        test::AxisEdgeSource src{bool(vertical_line), kCol + (c + 0.5f) / 25.0f, polarity ? 1.0f : 0.0f,
                                 polarity ? 0.0f : 1.0f};
        const Film a = test::render(src, kSize, kSize, s);
        const Film l = test::render(src, kSize, kSize, full);
        for (int y = 0; y < kSize; ++y)
          for (int x = 0; x < kSize; ++x) {
            const size_t i = size_t(y) * kSize + x;
            const bool on_edge = (vertical_line ? x : y) == kCol;
            SCOPED_TRACE(testing::Message() << tables << " vertical_line " << vertical_line << " polarity "
                                            << polarity << " c " << c << " pixel " << x << "," << y);
            if (on_edge) {
              EXPECT_EQ(a.level[i], vertical_line ? 3 : 3 + 4);  // refined, oriented across the edge
              EXPECT_NEAR(a.radiance[i].r, l.radiance[i].r, 1e-6f);
              // The lattice result itself: before the edge lie two corners (1/4 each) and
              // the inner points of columns 1..c (one per column).
              const float expect_before = (c + 0.5f) / 25.0f;
              const float before = polarity ? 1.0f : 0.0f;
              const float expected = before * expect_before + (1.0f - before) * (1.0f - expect_before);
              EXPECT_NEAR(a.radiance[i].r, expected, 1e-6f);
            } else {
              EXPECT_EQ(a.level[i], 1);
              EXPECT_EQ(a.rays[i], 1);
            }
          }
      }
}

TEST(AdaptiveEdges, PaperTablesMatchLatticeAtAll25Positions) { check_edges("paper"); }
TEST(AdaptiveEdges, TunedTablesMatchLatticeAtAll25Positions) { check_edges("tuned"); }

}  // namespace
}  // namespace zz
