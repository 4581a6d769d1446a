// The antialiasing through the whole renderer: colour distances exactly at eps, eps = 0
// and huge, frames that are all background or all one colour, sizes that are not
// multiples of 64, 1x1 and 1xN frames, extreme aspect ratios (4096x1, 1x4096).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "robust_scenes.h"

namespace zz {
namespace {

// Left half emits a, right half b; the camera looks straight at the split x = 0, which
// falls on the middle corner column (even width): only the two pixel columns touching it
// can see both colours.
Scene split_wall(float a, float b) {
  Scene s;
  for (float e : {a, b}) {
    Material m = test::diffuse_material(glm::vec3(0.0f));
    m.emissive = glm::vec3(e);
    s.materials.push_back(m);
  }
  test::add_quad(s, {-100, -100, 0}, {0, -100, 0}, {0, 100, 0}, {-100, 100, 0}, 0);
  test::add_quad(s, {0, -100, 0}, {100, -100, 0}, {100, 100, 0}, {0, 100, 0}, 1);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.5f));
  s.max_depth = 0;
  s.finalize_materials();
  return s;
}

RenderSettings adaptive(int w, int h, float eps, Filter filter = Filter::Box) {
  RenderSettings s = robust::settings(w, h, AaMode::Adaptive);
  s.adaptive.eps = eps;
  s.adaptive.filter = filter;
  return s;
}

TEST(AaFrame, DistanceExactlyAtEpsIsNoDiscontinuity) {
  const float a = 0.3f, b = 0.37f;
  const ToneMap tm;
  const float d = std::abs(tm.apply(b) - tm.apply(a));
  RenderStats st;
  robust::render(split_wall(a, b), adaptive(32, 16, d), &st);
  EXPECT_EQ(st.aa.level2_pixels, 0u) << "rho == eps must not refine";
  robust::render(split_wall(a, b), adaptive(32, 16, std::nextafter(d, 0.0f)), &st);
  EXPECT_GT(st.aa.level2_pixels, 0u) << "rho just above eps must refine";
  EXPECT_LE(st.aa.level2_pixels, 16u * 2u) << "only the columns touching the split";
}

TEST(AaFrame, EpsZeroAndHuge) {
  RenderStats st;
  // eps = 0: a constant image is continuous (distance 0 <= 0), the split refines.
  const Film flat = robust::render(robust::emissive_wall(glm::vec3(0.4f)), adaptive(40, 30, 0.0f), &st);
  EXPECT_EQ(st.aa.level2_pixels, 0u);
  for (const glm::vec3& c : flat.radiance) ASSERT_EQ(c, glm::vec3(0.4f));
  robust::render(split_wall(0.3f, 0.31f), adaptive(40, 30, 0.0f), &st);
  EXPECT_GE(st.aa.level2_pixels, 30u);
  // eps huge: nothing refines; the image is the mean of each pixel's corners.
  const Film coarse = robust::render(split_wall(0.0f, 1e6f), adaptive(40, 30, 1e30f), &st);
  EXPECT_EQ(st.aa.level2_pixels, 0u);
  EXPECT_EQ(robust::bad_values(coarse), 0u);
  // Corners left of the split (corner columns 0..19) see 0, right of it (21..40) 1e6; the
  // middle column 20 lies on the split and sees either. So pixels 0..18 are 0, 21..39 are
  // 1e6, and pixels 19 and 20 share column 20: with k of its two corners seeing 1e6, pixel
  // 19 is k/4 * 1e6 and pixel 20 (2 + k)/4 * 1e6 (exact in float: quarters of 1e6).
  ASSERT_EQ(coarse.width, 40);
  ASSERT_EQ(coarse.height, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      const glm::vec3 c = coarse.radiance[size_t(y) * 40 + x];
      ASSERT_EQ(c.r, c.g) << x << "," << y;
      ASSERT_EQ(c.r, c.b) << x << "," << y;
      if (x <= 18) {
        ASSERT_EQ(c.r, 0.0f) << x << "," << y;
      }
      if (x >= 21) {
        ASSERT_EQ(c.r, 1e6f) << x << "," << y;
      }
    }
  for (int y = 0; y < 30; ++y) {
    const float left = coarse.radiance[size_t(y) * 40 + 19].r, right = coarse.radiance[size_t(y) * 40 + 20].r;
    const float k = left / 2.5e5f;  // corners of column 20 (of this row's pixels) seeing 1e6
    EXPECT_TRUE(k == 0.0f || k == 1.0f || k == 2.0f) << "row " << y << ": " << left;
    EXPECT_EQ(right, (2.0f + k) * 2.5e5f) << "row " << y;
  }
}

TEST(AaFrame, AllBackgroundAndAllIdenticalFrames) {
  Scene empty = robust::emissive_wall(glm::vec3(1.0f));
  empty.positions.clear(), empty.normals.clear(), empty.uvs.clear(), empty.material_of.clear();
  empty.background = glm::vec3(0.25f, 0.5f, 2.0f);
  for (Filter filter : {Filter::Box, Filter::Mitchell})
    for (auto [w, h] : {std::pair{1, 1}, {1, 7}, {7, 1}, {64, 64}, {65, 3}, {130, 129}}) {
      SCOPED_TRACE(testing::Message() << w << "x" << h << " filter " << int(filter));
      RenderStats st;
      const Film f = robust::render(empty, adaptive(w, h, 0.0f, filter), &st);
      EXPECT_EQ(st.aa.level2_pixels, 0u);
      EXPECT_EQ(st.aa.pixels, uint64_t(w) * h);
      for (const glm::vec3& c : f.radiance) ASSERT_NEAR(c.b, 2.0f, filter == Filter::Box ? 0.0f : 2e-6f);
      const Film g = robust::render(robust::emissive_wall(glm::vec3(0.7f)), adaptive(w, h, 0.0f, filter), &st);
      EXPECT_EQ(st.aa.level2_pixels, 0u);
      for (const glm::vec3& c : g.radiance) ASSERT_NEAR(c.r, 0.7f, filter == Filter::Box ? 0.0f : 1e-6f);
    }
}

TEST(AaFrame, OddSizesAndExtremeAspectRatios) {
  const Scene scene = robust::shadow_scene({});
  for (auto [w, h] : {std::pair{1, 1}, {1, 33}, {33, 1}, {65, 65}, {127, 63}, {4096, 1}, {1, 4096}, {2000, 3}}) {
    for (Filter filter : {Filter::Box, Filter::Mitchell}) {
      SCOPED_TRACE(testing::Message() << w << "x" << h << " filter " << int(filter));
      RenderSettings s = adaptive(w, h, 0.1f, filter);
      s.threads = 2;
      RenderStats st;
      const Film a = robust::render(scene, s, &st);
      EXPECT_EQ(st.aa.pixels, uint64_t(w) * h);
      EXPECT_EQ(robust::bad_values(a), 0u);
      for (uint8_t r : a.rays) ASSERT_GE(r, 1);
      s.threads = 1;
      s.tile_size = 7;
      EXPECT_TRUE(robust::bit_identical(a, robust::render(scene, s))) << "tile size / threads changed the image";
    }
    RenderStats st;
    const Film none = robust::render(scene, robust::settings(w, h, AaMode::None), &st);
    EXPECT_EQ(st.samples, uint64_t(w) * h);
    EXPECT_EQ(robust::bad_values(none), 0u);
  }
}

}  // namespace
}  // namespace zz
