// The level-1 case table against ALGORITHM.md §4, row by row.
#include <gtest/gtest.h>

#include "aa/case_table.h"

namespace zz {
namespace {

TEST(CaseTable, EveryRowMatchesTheSpec) {
  // mask bits: a0=d(A,B) a1=d(C,D) a2=d(A,C) a3=d(B,D). Worked out by hand from the rule:
  // horizontal if (!a2 or !a3) and (a0 and a1); else vertical if (!a0 or !a1) and
  // (a2 and a3); else horizontal if any; else none.
  constexpr PixelCase N = PixelCase::None, Hz = PixelCase::Horizontal, V = PixelCase::Vertical;
  constexpr PixelCase expected[16] = {
      N,   // 0000
      Hz,  // 0001 a0
      Hz,  // 0010 a1
      Hz,  // 0011 a0 a1: rule 1
      Hz,  // 0100 a2
      Hz,  // 0101 a0 a2
      Hz,  // 0110 a1 a2
      Hz,  // 0111 a0 a1 a2: rule 1 (!a3)
      Hz,  // 1000 a3
      Hz,  // 1001 a0 a3
      Hz,  // 1010 a1 a3
      Hz,  // 1011 a0 a1 a3: rule 1 (!a2)
      V,   // 1100 a2 a3: rule 2
      V,   // 1101 a0 a2 a3: rule 2 (!a1)
      V,   // 1110 a1 a2 a3: rule 2 (!a0)
      Hz,  // 1111 all: rule 3
  };
  for (int m = 0; m < 16; ++m) EXPECT_EQ(kCaseTable[m], expected[m]) << "mask " << m;
}

TEST(CaseTable, OrientationIsOpenWhereNeitherOfTheFirstTwoClausesDecides) {
  // Decided: rule 1 (0011 0111 1011) and rule 2 (1100 1101 1110); open: none, one side,
  // two adjacent sides (a corner cut off), 1111.
  constexpr int decided[] = {0b0011, 0b0111, 0b1011, 0b1100, 0b1101, 0b1110};
  for (int m = 0; m < 16; ++m) {
    bool is_decided = false;
    for (int d : decided) is_decided |= m == d;
    EXPECT_EQ(orientation_open(m), !is_decided) << "mask " << m;
  }
}

}  // namespace
}  // namespace zz
