// The texture spread pyramid (render/texture_range.h) against brute force, and the normal
// map's spread widening the highlight flag (render/specular_peak.h).
#include "render/texture_range.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "scene/scene.h"

namespace zz {
namespace {

Texture random_texture(int w, int h, uint32_t seed, TextureWrap wrap = TextureWrap::Repeat) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Texture t;
  t.width = w, t.height = h;
  t.wrap_s = t.wrap_t = wrap;
  for (int i = 0; i < w * h; ++i) t.texels.push_back({u(rng), u(rng), u(rng), 1.0f});
  return t;
}

// The RMS deviation of texels [x0, x1] x [y0, y1] (wrapped by the texture's modes).
glm::vec3 brute_deviation(const Texture& t, long x0, long x1, long y0, long y1) {
  TextureMoments m;
  for (long y = y0; y <= y1; ++y)
    for (long x = x0; x <= x1; ++x) {
      const glm::vec3 v(t.texel(size_t(wrap_index(y, t.height, t.wrap_t)) * size_t(t.width) +
                                size_t(wrap_index(x, t.width, t.wrap_s))));
      m.sum += v, m.sum_sq += v * v, m.count += 1.0f;
    }
  return m.deviation();
}

// Up to 5 x 5 texels the moments are those of exactly the texels bilinear filtering reads
// anywhere in the box, the wrapped ones across the border included, in every wrap mode.
TEST(TextureSpread, SmallBoxesReadExactlyTheTexelsFilteringReads) {
  for (TextureWrap wrap : {TextureWrap::Repeat, TextureWrap::MirroredRepeat, TextureWrap::ClampToEdge}) {
    const Texture t = random_texture(37, 29, 7 + int(wrap), wrap);
    const TextureSpread spread(t);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> where(-1.5f, 2.5f), size(0.0f, 3.0f);
    for (int i = 0; i < 2000; ++i) {
      const glm::vec2 lo(where(rng), where(rng));
      const glm::vec2 hi = lo + glm::vec2(size(rng) / 37.0f, size(rng) / 29.0f);
      const long x0 = long(std::floor(double(lo.x) * 37 - 0.5)), x1 = long(std::floor(double(hi.x) * 37 - 0.5)) + 1;
      const long y0 = long(std::floor(double(lo.y) * 29 - 0.5)), y1 = long(std::floor(double(hi.y) * 29 - 0.5)) + 1;
      if (wrap == TextureWrap::ClampToEdge && (lo.x < -1.0f || hi.x > 2.0f || lo.y < -1.0f || hi.y > 2.0f)) continue;
      const TextureMoments m = spread.over(t, lo, hi);
      // Each texel once: a span across a repeat border is two wrapped runs.
      if (wrap == TextureWrap::Repeat) {
        EXPECT_EQ(m.count, float((x1 - x0 + 1) * (y1 - y0 + 1)));
        const glm::vec3 expected = brute_deviation(t, x0, x1, y0, y1), got = m.deviation();
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(got[c], expected[c], 1e-3f) << "box " << lo.x << "," << lo.y << " " << hi.x << "," << hi.y;
      } else {
        // Mirrored and clamped texels repeat across the border; each counts once: the
        // moments are those of the set of texels read.
        std::set<size_t> read;
        for (long y = y0; y <= y1; ++y)
          for (long x = x0; x <= x1; ++x)
            read.insert(size_t(wrap_index(y, t.height, wrap)) * size_t(t.width) + size_t(wrap_index(x, t.width, wrap)));
        TextureMoments expected;
        for (size_t i : read) {
          const glm::vec3 v(t.texel(i));
          expected.sum += v, expected.sum_sq += v * v, expected.count += 1.0f;
        }
        ASSERT_EQ(m.count, expected.count) << "box " << lo.x << "," << lo.y << " " << hi.x << "," << hi.y;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(m.deviation()[c], expected.deviation()[c], 1e-3f);
      }
    }
  }
}

// Larger boxes read whole blocks: a flat region stays flat, a box across a step sees the
// step, and a box over whole periods sees the whole texture.
TEST(TextureSpread, LargeBoxesSeeTheBlocksUnderThem) {
  Texture t;
  t.width = 256, t.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 256; ++x) t.texels.push_back(x < 128 ? glm::vec4(0.2f, 0.5f, 1.0f, 1.0f) : glm::vec4(0.8f, 0.5f, 1.0f, 1.0f));
  const TextureSpread spread(t);
  EXPECT_EQ(spread.over(t, {0.05f, 0.1f}, {0.2f, 0.5f}).deviation(), glm::vec3(0.0f));  // 38 texels, all 0.2
  const glm::vec3 across = spread.over(t, {0.4f, 0.1f}, {0.6f, 0.5f}).deviation();
  EXPECT_GT(across.r, 0.25f);  // half 0.2, half 0.8: 0.3
  EXPECT_LE(across.r, 0.3f + 1e-5f);
  EXPECT_EQ(across.g, 0.0f);
  const glm::vec3 wrapped = spread.over(t, {0.9f, 0.1f}, {1.1f, 0.5f}).deviation();  // both halves, across u = 1
  EXPECT_GT(wrapped.r, 0.25f);
  EXPECT_NEAR(spread.over(t, {-3.0f, 0.0f}, {5.0f, 1.0f}).deviation().r, 0.3f, 1e-4f);
  EXPECT_NEAR(spread.over(t, {NAN, 0.0f}, {0.1f, 1.0f}).deviation().r, 0.3f, 1e-4f);  // unknown: everything
}

// A one-material scene whose normal map is flat or noisy.
struct NormalMapped {
  Scene scene;
  std::vector<TextureSpread> spreads;
  explicit NormalMapped(float noise, float scale = 1.0f) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-noise, noise);
    Texture t;
    t.width = t.height = 64;
    for (int i = 0; i < 64 * 64; ++i) t.texels.push_back({0.5f + u(rng), 0.5f + u(rng), 1.0f, 1.0f});
    scene.textures.push_back(t);
    Material m;
    m.normal_texture.index = 0;
    m.normal_scale = scale;
    scene.materials.push_back(m);
    scene.finalize_materials();
    spreads = normal_map_spreads(scene);
  }
  void corners(glm::vec2 uv_lo, glm::vec2 uv_hi, SurfaceProbe c[4]) const {
    const glm::vec2 uv[4] = {uv_lo, {uv_hi.x, uv_lo.y}, {uv_lo.x, uv_hi.y}, uv_hi};
    for (int k = 0; k < 4; ++k) c[k].material = 0, c[k].uv0 = uv[k];
  }
};

TEST(NormalMapSpread, IsTheNormalsDeviationOverTheCornersBox) {
  SurfaceProbe c[4];
  const NormalMapped flat(0.0f);
  flat.corners({0.1f, 0.1f}, {0.2f, 0.2f}, c);
  EXPECT_EQ(normal_map_spread(flat.scene, flat.spreads, c), 0.0f);

  const NormalMapped noisy(0.2f);  // x, y uniform in +-0.4 as normals: RMS 0.4 / sqrt(3) each
  noisy.corners({0.1f, 0.1f}, {0.6f, 0.6f}, c);
  const float expected = kSpreadDeviations * std::sqrt(2.0f) * 0.4f / std::sqrt(3.0f);
  EXPECT_NEAR(normal_map_spread(noisy.scene, noisy.spreads, c), expected, 0.1f * expected);
  const NormalMapped unscaled(0.2f, 0.0f);  // normalTexture.scale 0: the map does nothing
  unscaled.corners({0.1f, 0.1f}, {0.6f, 0.6f}, c);
  EXPECT_EQ(normal_map_spread(unscaled.scene, unscaled.spreads, c), 0.0f);

  noisy.corners({0.1f, 0.1f}, {0.6f, 0.6f}, c);
  c[2].material = 1;  // two materials: not one map's pixel
  EXPECT_EQ(normal_map_spread(noisy.scene, noisy.spreads, c), 0.0f);
  EXPECT_EQ(normal_map_spread(noisy.scene, {}, c), 0.0f);  // no spreads built
}

// A shiny floor whose four corners all face away from the highlight's peak: the bilinear
// model finds nothing, but with a noisy normal map under them it flags the pixel (the
// lamp's hammered metal, whose highlights peaked on texels between the corners).
TEST(NormalMapSpread, WidensTheHighlightFlagUnderANoisyMap) {
  NormalMapped noisy(0.2f);
  Light light;
  light.position = {1.0f, 0.0f, 1.0f};
  noisy.scene.lights.push_back(light);
  const glm::vec3 eye(-1.0f, 0.0f, 1.0f);
  const glm::vec3 at[4] = {{0.10f, 0.0f, 0.0f}, {0.12f, 0.0f, 0.0f}, {0.10f, 0.02f, 0.0f}, {0.12f, 0.02f, 0.0f}};
  SurfaceProbe c[4];
  noisy.corners({0.1f, 0.1f}, {0.3f, 0.3f}, c);
  for (int k = 0; k < 4; ++k) {
    c[k].position = at[k];
    c[k].normal = {0, 0, 1};
    c[k].view = glm::normalize(eye - at[k]);
    c[k].specular = glm::vec3(0.04f);
    c[k].shininess = 1000.0f;
  }
  const glm::vec3 visible(1e-3f);
  EXPECT_EQ(hidden_highlight(noisy.scene, c, visible), glm::vec3(0.0f));
  EXPECT_GT(hidden_highlight(noisy.scene, c, visible, nullptr, INFINITY, &noisy.spreads).r, 0.0f);
  const NormalMapped flat(0.0f);
  Scene lit = flat.scene;
  lit.lights.push_back(light);
  EXPECT_EQ(hidden_highlight(lit, c, visible, nullptr, INFINITY, &flat.spreads), glm::vec3(0.0f));
}

// The frame's memory check counts the pyramid: 4 x 4 blocks and their halvings, each normal
// map once however many materials use it.
TEST(NormalMapSpread, BytesCountEachLevelAndEachMapOnce) {
  EXPECT_EQ(TextureSpread::bytes(64, 64), uint64_t(16 * 16 + 8 * 8 + 4 * 4 + 2 * 2 + 1) * sizeof(TextureMoments));
  EXPECT_EQ(TextureSpread::bytes(3, 100), uint64_t(25 + 12 + 6 + 3 + 1) * sizeof(TextureMoments));
  EXPECT_EQ(TextureSpread::bytes(0, 100), 0u);
  NormalMapped one(0.1f);
  const uint64_t single = normal_map_spread_bytes(one.scene);
  EXPECT_EQ(single, TextureSpread::bytes(64, 64));
  one.scene.materials.push_back(one.scene.materials[0]);  // a second material, the same map
  EXPECT_EQ(normal_map_spread_bytes(one.scene), single);
  one.scene.materials[1].normal_texture.index = -1;
  one.scene.materials[0].normal_texture.index = -1;
  EXPECT_EQ(normal_map_spread_bytes(one.scene), 0u);
}

}  // namespace
}  // namespace zz
