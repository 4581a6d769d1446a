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

}  // namespace
}  // namespace zz
