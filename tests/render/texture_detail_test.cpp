// The texture detail flag (render/texture_detail.h): the pyramid's box means and the
// detail a pixel's corners miss.
#include "render/texture_detail.h"

#include <gtest/gtest.h>

#include "scene/scene.h"

namespace zz {
namespace {

Texture grey_texture(int w, int h, float (*value)(int x, int y)) {
  Texture t;
  t.width = w;
  t.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) t.texels.push_back(glm::vec4(glm::vec3(value(x, y)), 1.0f));
  return t;
}

TEST(TextureDetail, PyramidLevelsAreBoxMeans) {
  const Texture checker = grey_texture(8, 8, [](int x, int y) { return float((x + y) % 2); });
  const TexturePyramid p(checker);
  ASSERT_EQ(p.levels.size(), 4u);  // 8 (the texture), 4, 2, 1
  EXPECT_EQ(p.levels[1].width, 4);
  EXPECT_FLOAT_EQ(p.levels[1].texels[5].r, 0.5f);
  EXPECT_FLOAT_EQ(p.levels[3].texels[0].r, 0.5f);
  // The whole texture: its mean; a box inside one texel: that texel.
  EXPECT_NEAR(p.box_mean(checker, {0.0f, 0.0f}, {1.0f, 1.0f}).r, 0.5f, 1e-6f);
  EXPECT_NEAR(p.box_mean(checker, {0.5f / 8, 1.5f / 8}, {0.5f / 8, 1.5f / 8}).r, 1.0f, 1e-6f);  // texel (0, 1)
  // An odd size keeps its last row and column.
  const Texture odd = grey_texture(5, 3, [](int x, int) { return float(x); });
  const TexturePyramid q(odd);
  EXPECT_EQ(q.levels.back().width, 1);
  EXPECT_EQ(q.levels.back().height, 1);
}

// One emissive material whose texture is black but for a white column one texel wide.
struct StrokeScene {
  Scene scene;
  std::vector<TexturePyramid> pyramids;
  StrokeScene() {
    scene.textures.push_back(grey_texture(64, 64, [](int x, int) { return x == 32 ? 1.0f : 0.0f; }));
    Material m;
    m.base_color = glm::vec3(0.0f);
    m.emissive = glm::vec3(1.0f);
    m.emissive_texture.index = 0;
    scene.materials.push_back(m);
    scene.materials.push_back(m);
    scene.finalize_materials();
    pyramids = texture_pyramids(scene);
  }
  // A pixel whose corners sample the texture at u in [u0, u1], v in [0.4, 0.45].
  void corners(float u0, float u1, SurfaceProbe c[4]) const {
    const float us[4] = {u0, u1, u0, u1}, vs[4] = {0.4f, 0.4f, 0.45f, 0.45f};
    for (int k = 0; k < 4; ++k) {
      c[k] = SurfaceProbe{};
      c[k].material = 0;
      c[k].uv0 = {us[k], vs[k]};
    }
  }
};

TEST(TextureDetail, AStrokeBetweenTheCornersIsFound) {
  const StrokeScene s;
  SurfaceProbe c[4];
  s.corners(28.0f / 64, 37.0f / 64, c);  // the stroke (texel 32) is a ninth of the footprint
  const glm::vec3 hidden = hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f));
  EXPECT_NEAR(hidden.r, 1.0f / 9.0f, 0.06f);
  // All black: next to nothing (the trilinear estimate leaks a little of the stroke from the
  // power-of-two block it shares with the footprint: 0.008 here, a fifteenth of the stroke's).
  s.corners(40.0f / 64, 49.0f / 64, c);
  EXPECT_LT(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)).r, 0.02f);
  s.corners(2.0f / 64, 11.0f / 64, c);  // far from it: exactly nothing
  EXPECT_EQ(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)).r, 0.0f);
}

TEST(TextureDetail, NoEstimateAcrossMaterialsOrSeams) {
  const StrokeScene s;
  SurfaceProbe c[4];
  s.corners(28.0f / 64, 37.0f / 64, c);
  c[3].material = 1;  // another material at one corner: an edge, not detail
  EXPECT_EQ(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)), glm::vec3(0.0f));
  s.corners(0.05f, 0.95f, c);  // a UV seam: the corners' box spans most of the texture
  EXPECT_EQ(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)), glm::vec3(0.0f));
  s.corners(28.0f / 64, 37.0f / 64, c);
  for (SurfaceProbe& p : c) p.material = ~0u;  // misses
  EXPECT_EQ(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)), glm::vec3(0.0f));
}

}  // namespace
}  // namespace zz
