#include "viewer/view_tweaks.h"

#include <gtest/gtest.h>

namespace zz {
namespace {

// `[` reaches eps 0 (every colour difference refines) and `]` leaves it: at 0 the steps
// used to be stuck (0 x 1.25 = 0) and `[` raised eps to 1e-4.
TEST(ViewTweaks, EpsStepsReachZeroAndLeaveIt) {
  ViewTweaks t;
  t.eps = 0.0f;
  t.eps_down();
  EXPECT_EQ(t.eps, 0.0f);
  t.eps_up();
  EXPECT_EQ(t.eps, ViewTweaks::kEpsSmallest);
  t.eps_up();
  EXPECT_FLOAT_EQ(t.eps, ViewTweaks::kEpsSmallest * ViewTweaks::kEpsStep);
  for (int i = 0; i < 3; ++i) t.eps_down();
  EXPECT_EQ(t.eps, 0.0f);
  t.eps = 0.1f;
  t.eps_up();
  t.eps_up();
  EXPECT_EQ(t.eps, 0.15625f);  // 0.1 x 1.25^2, as the Xvfb key test renders it
  for (int i = 0; i < 40; ++i) t.eps_up();
  EXPECT_EQ(t.eps, 1.0f);
}

TEST(ViewTweaks, ApplyReachesTheAdaptiveSettings) {
  ViewTweaks t;
  t.eps = 0.02f;
  t.mitchell = true;
  RenderSettings s;
  apply_tweaks(t, s);
  EXPECT_EQ(s.adaptive.eps, 0.02f);
  EXPECT_EQ(s.adaptive.filter, Filter::Mitchell);
}

// E turns the map off and on: the map's crease goes with it, as `render --edges off` and
// `--edges vulkan` set it (exploratory testing: with E the viewer showed an image no
// render setting makes, the highlight flag leaving normal steps to a map not there).
TEST(ViewTweaks, TheMapsCreaseFollowsTheMap) {
  ViewTweaks t;
  t.map_crease = 0.42f;
  RenderSettings s;
  apply_tweaks(t, s);
  EXPECT_EQ(s.adaptive.map_crease, 0.42f);
  t.edges = false;
  apply_tweaks(t, s);
  EXPECT_EQ(s.adaptive.map_crease, 0.0f);
  t.edges = true;
  apply_tweaks(t, s);
  EXPECT_EQ(s.adaptive.map_crease, 0.42f);
}

}  // namespace
}  // namespace zz
