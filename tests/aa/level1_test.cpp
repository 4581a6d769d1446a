// Level 1's decision (decide_level1 in aa/adaptive_pixel.h): which pixels refine and how
// they are oriented, with the visibility map's edge direction.
#include <gtest/gtest.h>

#include "aa/adaptive_pixel.h"

namespace zz {
namespace {

// Display colours of the corners TL, TR, BL, BR: 0 where `dark` has the bit, else 1.
Rgb4 corners(int dark) {
  alignas(16) float v[4];
  for (int i = 0; i < 4; ++i) v[i] = (dark >> i) & 1 ? 0.0f : 1.0f;
  const float4 c = float4::load(v);
  return {c, c, c};
}

const float4 kEps(0.05f);
const int4 kSameSig(make_signature(3u, 0, 0));

TEST(Level1, TheMapsEdgeDirectionOrientsOnlyWhatTheCornersLeaveOpen) {
  // A cut off (TL dark): a0 = d(A,B) and a2 = d(A,C), no clause decides; the paper takes
  // horizontal, an edge along x takes vertical.
  const Level1 cut = decide_level1(corners(0b0001), kSameSig, kEps, /*geo=*/true, false, /*along_x=*/false);
  EXPECT_TRUE(cut.refine);
  EXPECT_EQ(cut.orientation, Orientation::Horizontal);
  EXPECT_EQ(decide_level1(corners(0b0001), kSameSig, kEps, true, false, true).orientation, Orientation::Vertical);
  // The left half dark: a0 and a1, rule 1 says horizontal whatever the map says.
  EXPECT_EQ(decide_level1(corners(0b0101), kSameSig, kEps, true, false, true).orientation, Orientation::Horizontal);
  // The top half dark: rule 2 says vertical either way.
  EXPECT_EQ(decide_level1(corners(0b0011), kSameSig, kEps, true, false, false).orientation, Orientation::Vertical);
  EXPECT_EQ(decide_level1(corners(0b0011), kSameSig, kEps, true, false, true).orientation, Orientation::Vertical);
  // No case: a geo pixel goes on, oriented by the map; without the flag it does not refine.
  const Level1 none = decide_level1(corners(0), kSameSig, kEps, true, false, true);
  EXPECT_TRUE(none.refine);
  EXPECT_EQ(none.orientation, Orientation::Vertical);
  EXPECT_FALSE(decide_level1(corners(0), kSameSig, kEps, false, false, false).refine);
}

TEST(Level1, SignaturesAreDiscontinuitiesToo) {
  // Equal colours, the TL corner on something else: a corner cut like the colour one.
  const int32_t one = make_signature(3u, 0, 0), other = make_signature(7u, 0, 0);
  const Level1 l = decide_level1(corners(0), int4(other, one, one, one), kEps, false, false);
  EXPECT_TRUE(l.refine);
  EXPECT_EQ(l.orientation, Orientation::Horizontal);
}

}  // namespace
}  // namespace zz
