// Scale invariance: the same scene scaled by 1e-4 ... 1e6 and moved 1e5 scene units from
// the origin renders the same image. Shadow acne (self-shadowed speckles on the lit
// floor) and light leaks (lit speckles inside the box's shadow) are counted separately:
// both must be zero; the rest of the image must match the unscaled one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "robust_scenes.h"

namespace zz {
namespace {

constexpr int kW = 96, kH = 64;

// Display luminance byte per pixel (max of the channels).
std::vector<int> display_max(const Film& film) {
  const std::vector<uint8_t> rgb = display_bytes(film, ToneMap{});
  std::vector<int> out(size_t(film.width) * film.height);
  for (size_t i = 0; i < out.size(); ++i) out[i] = std::max({rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]});
  return out;
}

// Pixel i and its 8 neighbours all satisfy pred (interior of a region: away from edges).
template <class Pred>
bool interior(const std::vector<int>& img, int x, int y, Pred pred) {
  if (x == 0 || y == 0 || x == kW - 1 || y == kH - 1) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (!pred(img[size_t(y + dy) * kW + (x + dx)])) return false;
  return true;
}

struct Comparison {
  int lit = 0, shadow = 0;     // reference interior pixels of each kind
  int acne = 0, leaks = 0;     // interior pixels that changed kind
  int differing = 0;           // pixels differing by more than 4/255
  double mean_abs = 0.0;       // mean |difference| in display bytes
};

// 1 where the unscaled scene's pixel-centre ray hits the floor (triangles 0 and 1): the
// acne and leak counts look at floor pixels only (a moved silhouette is neither).
std::vector<int> floor_mask() {
  const Scene s = robust::shadow_scene({});
  const Bvh bvh = Bvh::build(s.positions);
  const CameraRays rays(s.cameras[0], kW, kH);
  std::vector<int> mask(size_t(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const Hit h = bvh.intersect1(Ray{rays.origin, rays.direction(x + 0.5f, y + 0.5f)});
      mask[size_t(y) * kW + x] = h.hit() && h.prim < 2;
    }
  return mask;
}

Comparison compare(const Film& reference, const Film& test) {
  static const std::vector<int> on_floor = floor_mask();
  const std::vector<int> a = display_max(reference), b = display_max(test);
  const std::vector<uint8_t> ra = display_bytes(reference, ToneMap{}), rb = display_bytes(test, ToneMap{});
  Comparison c;
  auto lit = [](int v) { return v > 60; };
  auto dark = [](int v) { return v < 8; };
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const size_t i = size_t(y) * kW + x;
      const bool floor = interior(on_floor, x, y, [](int f) { return f != 0; });
      if (floor && interior(a, x, y, lit)) {
        ++c.lit;
        if (b[i] < a[i] / 2) {
          ++c.acne;
          std::printf("[ scale ]   acne at pixel (%d, %d): %d, unscaled %d\n", x, y, b[i], a[i]);
        }
      }
      if (floor && interior(a, x, y, dark)) {
        ++c.shadow;
        c.leaks += b[i] > 16;
      }
      int d = 0;
      for (int k = 0; k < 3; ++k) {
        const int e = std::abs(int(ra[3 * i + k]) - int(rb[3 * i + k]));
        d = std::max(d, e);
        c.mean_abs += e;
      }
      c.differing += d > 4;
    }
  c.mean_abs /= 3.0 * kW * kH;
  return c;
}

TEST(Scale, SameImageFrom1eMinus4To1e6AndFarFromTheOrigin) {
  for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
    const Film reference = robust::render(robust::shadow_scene({}), robust::settings(kW, kH, aa));
    for (double scale : {1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6})
      for (double far : {0.0, 1e5}) {
        // "Far" is in scene units (1e5 scene lengths): the absolute offset scales too, so
        // the float spacing relative to the scene is the same at every scale.
        const robust::Placement at{scale, glm::dvec3(far * scale, -0.5 * far * scale, 0.25 * far * scale)};
        SCOPED_TRACE(testing::Message() << "aa " << int(aa) << " scale " << scale << " offset " << far * scale);
        const Film film = robust::render(robust::shadow_scene(at), robust::settings(kW, kH, aa));
        ASSERT_EQ(robust::bad_values(film), 0u);
        const Comparison c = compare(reference, film);
        std::printf("[ scale ] aa=%d scale=%-6g offset=%-8g lit=%d shadow=%d acne=%d leaks=%d differing=%d mean|d|=%.3f\n",
                    int(aa), scale, far * scale, c.lit, c.shadow, c.acne, c.leaks, c.differing, c.mean_abs);
        EXPECT_GT(c.lit, kW * kH / 4);   // the criterion sees a lit floor ...
        EXPECT_GT(c.shadow, 100);         // ... and a shadow
        EXPECT_EQ(c.acne, 0);
        EXPECT_EQ(c.leaks, 0);
        // Rounding moves silhouettes and shadow edges by a fraction of a pixel only. Far
        // from the origin the vertices themselves are quantised (1e5 lengths: steps of
        // 1/1000 of the scene), which moves every edge by a few % of a pixel and flips
        // some adaptive refinement decisions: up to 2 % of the pixels.
        EXPECT_LE(c.differing, kW * kH / 50);
        EXPECT_LT(c.mean_abs, 0.5);
      }
  }
}

}  // namespace
}  // namespace zz
