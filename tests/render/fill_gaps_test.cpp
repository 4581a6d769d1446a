// Gaps between refined pixels (AdaptiveSettings::fill_gaps, --fill-gaps; fills_gap in
// aa/adaptive_pixel.h): an image pixel whose corners all miss a thin line, between two
// pixels that refine, refines too.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "aa/adaptive_pixel.h"
#include "core/film.h"
#include "core/tonemap.h"
#include "render/renderer.h"
#include "test_scenes.h"

namespace zz {
namespace {

TEST(FillsGap, BetweenTwoRefinedNeighboursAcrossThePixel) {
  EXPECT_TRUE(fills_gap(true, true, false, false));   // left and right
  EXPECT_TRUE(fills_gap(false, false, true, true));   // above and below
  EXPECT_FALSE(fills_gap(true, false, true, false));  // a corner of refined pixels: an edge's staircase
  EXPECT_FALSE(fills_gap(false, true, false, true));
  EXPECT_FALSE(fills_gap(true, false, false, false));
  EXPECT_FALSE(fills_gap(false, false, false, false));
}

constexpr int kSize = 48;
constexpr int kRow = 24;  // the stripes are vertical: any row will do

// A dim glowing ceiling at z = 5 with bright vertical stripes every 3 pixels: one over
// every pixel corner x = 3k, and one thin one in the middle of pixel 3k + 1, between its
// corners. Seen from below through a black alpha-BLEND pane of coverage 0.3 at z = 2 (an
// image pixel: eps_specular's), or, with `through_pane` false, straight. `across`: the
// camera turned a quarter, so the stripes run across the image (rows y = 3k + 1).
struct StripeScene {
  Scene scene;
  explicit StripeScene(bool through_pane, bool across = false) {
    Material dim = test::diffuse_material(glm::vec3(0.0f)), bright = dim, pane = dim;
    dim.emissive = glm::vec3(0.5f);
    bright.emissive = glm::vec3(1.0f);
    pane.alpha_mode = AlphaMode::Blend;
    pane.base_alpha = 0.3f;
    scene.materials = {dim, bright, pane};
    scene.cameras.push_back(
        Camera::look_at({0.3f, 0.2f, -2.5f}, {0.3f, 0.2f, 5}, across ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0), 0.5f));
    test::add_quad(scene, {-10, -10, 5}, {-10, 10, 5}, {10, 10, 5}, {10, -10, 5}, 0);  // faces -z
    // The stripes a hair in front of the ceiling, placed in pixel units along the row.
    const CameraRays rays(scene.cameras[0], kSize, kSize);
    auto world_x = [&](float px) {
      const glm::vec3 d = across ? rays.direction(float(kRow) + 0.5f, px) : rays.direction(px, float(kRow) + 0.5f);
      const glm::vec3 o = scene.cameras[0].position;
      return o.x + d.x * ((4.99f - o.z) / d.z);
    };
    auto stripe = [&](float from, float to) {
      float x0 = world_x(from), x1 = world_x(to);
      if (x0 > x1) std::swap(x0, x1);
      test::add_quad(scene, {x0, -10, 4.99f}, {x0, 10, 4.99f}, {x1, 10, 4.99f}, {x1, -10, 4.99f}, 1);
    };
    for (int k = 0; 3 * k <= kSize; ++k) {
      stripe(3.0f * float(k) - 0.2f, 3.0f * float(k) + 0.2f);
      stripe(3.0f * float(k) + 1.25f, 3.0f * float(k) + 1.75f);
    }
    if (through_pane) test::add_quad(scene, {-10, -10, 2}, {-10, 10, 2}, {10, 10, 2}, {10, -10, 2}, 2);
    scene.max_depth = 1;
    scene.finalize_materials();
  }
};

struct StripeRender {
  RenderStats stats;
  Film film;
};
StripeRender render_stripes(const StripeScene& s, bool fill_gaps, int tile_size = kTileSize, int threads = 0) {
  const Bvh bvh = Bvh::build(s.scene.positions);
  const Shader shader(s.scene, bvh);
  RenderSettings r;
  r.width = r.height = kSize;
  r.adaptive.eps = 0.05f;
  r.adaptive.eps_specular = 0.01f;
  r.adaptive.signature = kSignatureNone;
  r.adaptive.fill_gaps = fill_gaps;
  r.tile_size = tile_size;
  r.threads = threads;
  StripeRender out;
  render_frame(shader, s.scene.cameras[0], GeoMap{}, r, out.film, out.stats);
  return out;
}

// The gap pixels' (3k + 1) mean distance from the lattice's, in display units.
double gap_error(const Film& film, const Film& lattice, const ToneMap& tonemap) {
  double sum = 0.0;
  int n = 0;
  for (int y = 2; y < kSize - 2; ++y)
    for (int x = 1; x + 1 < kSize; x += 3) {
      const size_t i = size_t(y) * kSize + size_t(x);
      sum += std::fabs(tonemap.apply(film.radiance[i].g) - tonemap.apply(lattice.radiance[i].g));
      ++n;
    }
  return sum / n;
}

TEST(FillGaps, AThinLineBetweenTheCornersOfAnImagePixelIsFoundFromItsNeighbours) {
  const StripeScene scene(true);
  const StripeRender off = render_stripes(scene, false), on = render_stripes(scene, true);
  // The 25-point lattice through the same code, for what the gap pixels should hold.
  const Bvh bvh = Bvh::build(scene.scene.positions);
  const Shader shader(scene.scene, bvh);
  RenderSettings r;
  r.width = r.height = kSize;
  r.adaptive.refine_all = true;
  Film lattice;
  RenderStats lattice_stats;
  render_frame(shader, scene.scene.cameras[0], GeoMap{}, r, lattice, lattice_stats);

  EXPECT_EQ(off.stats.aa.specular_pixels, off.stats.aa.pixels);  // the pane fills the frame
  EXPECT_EQ(off.stats.aa.gap_pixels, 0u);
  // Without the rule every gap column stays at level 1, its corners both dark.
  const ToneMap tonemap{};
  const double missed = gap_error(off.film, lattice, tonemap);
  ASSERT_GT(missed, 0.02);
  // With it, the 16 columns of gap pixels refine (all but a row or two at the frame's edge
  // may already), and come within a third of the error.
  EXPECT_GE(on.stats.aa.gap_pixels, 15u * kSize);
  EXPECT_LE(on.stats.aa.gap_pixels, 16u * kSize);
  EXPECT_EQ(on.stats.aa.level2_pixels, off.stats.aa.level2_pixels + on.stats.aa.gap_pixels);
  EXPECT_LT(gap_error(on.film, lattice, tonemap), missed / 3.0);
}

// With the stripes along the image's columns and across its rows: a gap is filled from
// the neighbours on the left and right, or above and below, whichever tile holds them
// (mutation testing: the row below a tile left out of what its pixels see around them
// passed with the columns alone).
TEST(FillGaps, DecidesTheSameWhateverTheTilesAndThreads) {
  for (const bool across : {false, true}) {
    const StripeScene scene(true, across);
    const StripeRender reference = render_stripes(scene, true);
    EXPECT_GE(reference.stats.aa.gap_pixels, 15u * kSize) << across;
    for (int tile : {7, 16}) {
      for (int threads : {1, 2}) {
        const StripeRender other = render_stripes(scene, true, tile, threads);
        EXPECT_EQ(other.stats.aa.gap_pixels, reference.stats.aa.gap_pixels) << tile << " " << threads << " " << across;
        EXPECT_EQ(other.film.radiance, reference.film.radiance) << tile << " " << threads << " " << across;
      }
    }
  }
}

TEST(FillGaps, LeavesPixelsThatSeeNoImageAlone) {
  const StripeScene straight(false);
  const StripeRender off = render_stripes(straight, false), on = render_stripes(straight, true);
  EXPECT_EQ(on.stats.aa.specular_pixels, 0u);
  EXPECT_EQ(on.stats.aa.gap_pixels, 0u);
  EXPECT_EQ(on.film.radiance, off.film.radiance);
}

}  // namespace
}  // namespace zz
