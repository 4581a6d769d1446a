// The mirror's threshold (AdaptiveSettings::eps_specular, --eps-specular): pixels whose
// four corners all see a mirror's or a glass's image, or what lies behind a BLEND surface,
// compare colours with it.
#include <gtest/gtest.h>

#include <cmath>

#include "aa/hidden_detail.h"
#include "core/film.h"
#include "core/tonemap.h"
#include "render/renderer.h"
#include "render/scene_source.h"
#include "test_scenes.h"

namespace zz {
namespace {

TEST(ShowsAnImage, MirrorsAndGlassDoDielectricsAndDiffuseSurfacesDoNot) {
  WhittedMaterial m;
  EXPECT_FALSE(shows_an_image(m));
  m.mirror = glm::vec3(0.9f);
  EXPECT_TRUE(shows_an_image(m));
  m.mirror = glm::vec3(0.3f);  // a dark mirror shows mostly its own colour
  EXPECT_FALSE(shows_an_image(m));
  m.mirror = glm::vec3(0.9f);
  m.fresnel_mirror = true;  // paint's clear coat: 4 % at normal incidence
  EXPECT_FALSE(shows_an_image(m));
  WhittedMaterial glass;
  glass.transmission = glm::vec3(1.0f);
  EXPECT_TRUE(shows_an_image(glass));
}

TEST(ShowsAnImage, ABlendSurfaceThatLetsMostLightThroughDoes) {
  const WhittedMaterial opaque;  // what whitted_from_gltf makes of a diffuse pane
  Material pane;
  EXPECT_FALSE(shows_an_image(pane, opaque));
  pane.alpha_mode = AlphaMode::Blend;
  pane.base_alpha = 0.3f;  // the vase's: 70 % of what lies behind it
  EXPECT_TRUE(shows_an_image(pane, opaque));
  pane.base_alpha = 0.5f;  // half its own colour: not mostly an image
  EXPECT_FALSE(shows_an_image(pane, opaque));
  pane.alpha_mode = AlphaMode::Mask;  // a cut-out covers all or nothing
  pane.base_alpha = 0.3f;
  EXPECT_FALSE(shows_an_image(pane, opaque));
  WhittedMaterial glass;
  glass.transmission = glm::vec3(1.0f);
  EXPECT_TRUE(shows_an_image(Material{}, glass));
}

// A step of `step` in emission on a glowing ceiling at z = 5 (no lights: nothing but the
// glow varies), seen straight (the camera under it, looking up) or in a mirror floor (the
// camera above the floor, looking down); no visibility map, no signatures, so only the
// colour test can refine it.
// With `pane_alpha` > 0 the straight view looks through a black alpha-BLEND pane at z = 2
// of that coverage.
struct StepScene {
  Scene scene;
  explicit StepScene(bool in_mirror, float step = 0.07f, float pane_alpha = 0.0f) {
    Material dim = test::diffuse_material(glm::vec3(0.0f)), bright = dim, pane = dim;
    dim.emissive = glm::vec3(0.5f);
    bright.emissive = glm::vec3(0.5f + step);
    pane.alpha_mode = AlphaMode::Blend;
    pane.base_alpha = pane_alpha;
    scene.materials = {dim, bright, test::mirror_material(glm::vec3(0.95f)), pane};
    test::add_quad(scene, {-10, -10, 5}, {-10, 10, 5}, {0, 10, 5}, {0, -10, 5}, 0);  // faces -z
    test::add_quad(scene, {0, -10, 5}, {0, 10, 5}, {10, 10, 5}, {10, -10, 5}, 1);
    if (pane_alpha > 0.0f) test::add_quad(scene, {-10, -10, 2}, {-10, 10, 2}, {10, 10, 2}, {10, -10, 2}, 3);
    if (in_mirror) {
      test::add_quad(scene, {-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, 2);  // faces +z
      scene.cameras.push_back(Camera::look_at({0.3f, 0.2f, 2.5f}, {0.3f, 0.2f, 0}, {0, 1, 0}, 0.5f));
    } else {
      scene.cameras.push_back(Camera::look_at({0.3f, 0.2f, -2.5f}, {0.3f, 0.2f, 5}, {0, 1, 0}, 0.5f));
    }
    scene.max_depth = 1;
    scene.finalize_materials();
  }
};

struct StepRender {
  RenderStats stats;
  Film film;
};
StepRender render_step(const StepScene& s, float eps_specular, bool corner_field = true) {
  const Bvh bvh = Bvh::build(s.scene.positions);
  const Shader shader(s.scene, bvh);
  RenderSettings r;
  r.width = r.height = 48;
  r.adaptive.eps = 0.05f;
  r.adaptive.eps_specular = eps_specular;
  r.adaptive.signature = kSignatureNone;
  r.corner_field = corner_field;
  StepRender out;
  render_frame(shader, s.scene.cameras[0], GeoMap{}, r, out.film, out.stats);
  return out;
}

TEST(SpecularEps, AStepSeenInAMirrorRefinesAtTheMirrorsThreshold) {
  const StepScene mirror(true), direct(false);
  // The step shows between eps_specular and eps on the display, both ways.
  const StepRender plain = render_step(mirror, -1.0f);
  const ToneMap tonemap{};
  const glm::vec3 left = plain.film.radiance[size_t(24) * 48 + 2], right = plain.film.radiance[size_t(24) * 48 + 45];
  const float shown = std::fabs(tonemap.apply(right.g) - tonemap.apply(left.g));
  ASSERT_GT(shown, 0.015f);
  ASSERT_LT(shown, 0.045f);

  EXPECT_EQ(plain.stats.aa.level2_pixels, 0u);  // eps 0.05 sees nothing
  EXPECT_EQ(plain.stats.aa.specular_pixels, 0u);
  const StepRender tight = render_step(mirror, 0.01f);
  EXPECT_EQ(tight.stats.aa.specular_pixels, tight.stats.aa.pixels);  // the mirror fills the frame
  EXPECT_GE(tight.stats.aa.level2_pixels, 48u);                        // the step's column of pixels
  EXPECT_LE(tight.stats.aa.level2_pixels, 3u * 48u);
  // Per-tile corners decide the same pixels the same way, to the bit.
  const StepRender per_tile = render_step(mirror, 0.01f, false);
  EXPECT_EQ(per_tile.stats.aa.specular_pixels, tight.stats.aa.specular_pixels);
  EXPECT_EQ(per_tile.stats.aa.level2_pixels, tight.stats.aa.level2_pixels);
  EXPECT_EQ(per_tile.film.radiance, tight.film.radiance);
  // Seen straight, the same step is no mirror's image: eps holds.
  const StepRender straight = render_step(direct, 0.01f);
  EXPECT_EQ(straight.stats.aa.specular_pixels, 0u);
  EXPECT_EQ(straight.stats.aa.level2_pixels, 0u);
}

// A BLEND pane that lets 70 % through shows mostly what lies behind it, as a mirror does:
// the step behind it refines at the mirror's threshold; behind a pane of coverage 1/2, eps.
TEST(SpecularEps, AStepSeenThroughAThinBlendPaneRefinesAtTheMirrorsThreshold) {
  const StepScene thin(false, 0.1f, 0.3f), half(false, 0.1f, 0.5f);
  const StepRender plain = render_step(thin, -1.0f);
  const ToneMap tonemap{};
  const glm::vec3 left = plain.film.radiance[size_t(24) * 48 + 2], right = plain.film.radiance[size_t(24) * 48 + 45];
  const float shown = std::fabs(tonemap.apply(right.g) - tonemap.apply(left.g));
  ASSERT_GT(shown, 0.015f);  // between the thresholds, through the pane
  ASSERT_LT(shown, 0.045f);
  EXPECT_EQ(plain.stats.aa.level2_pixels, 0u);

  const StepRender tight = render_step(thin, 0.01f);
  EXPECT_EQ(tight.stats.aa.specular_pixels, tight.stats.aa.pixels);
  EXPECT_GE(tight.stats.aa.level2_pixels, 48u);
  EXPECT_LE(tight.stats.aa.level2_pixels, 3u * 48u);
  const StepRender half_pane = render_step(half, 0.01f);
  EXPECT_EQ(half_pane.stats.aa.specular_pixels, 0u);
  EXPECT_EQ(half_pane.stats.aa.level2_pixels, 0u);
}

}  // namespace
}  // namespace zz
