// The texture detail flag (render/texture_detail.h): the pyramid's box means and the
// detail a pixel's corners miss; the texture footprint correction.
#include "render/texture_detail.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "accel/bvh.h"
#include "aa/lattice.h"
#include "render/normal_map.h"
#include "render/scene_source.h"
#include "render/shader.h"
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
  // An odd size keeps its last row and column: they join the block beside them, so every
  // level's mean is the texture's (texel 4 of 5 was in no level, and the 1x1 level of
  // a width of 3 was the mean of texels 0 and 1).
  const Texture odd = grey_texture(5, 3, [](int x, int) { return float(x); });
  const TexturePyramid q(odd);
  ASSERT_EQ(q.levels.size(), 3u);  // 5x3 (the texture), 2x1, 1x1
  EXPECT_EQ(q.levels[1].width, 2);
  EXPECT_EQ(q.levels[1].height, 1);
  EXPECT_FLOAT_EQ(q.levels[1].texels[0].r, 0.5f);  // columns 0, 1
  EXPECT_FLOAT_EQ(q.levels[1].texels[1].r, 3.0f);  // columns 2, 3, 4
  EXPECT_FLOAT_EQ(q.levels.back().texels[0].r, 2.0f);  // the mean of 0..4
  const Texture three = grey_texture(3, 3, [](int x, int y) { return float(x + 3 * y); });
  EXPECT_FLOAT_EQ(TexturePyramid(three).levels.back().texels[0].r, 4.0f);
}

// The memory check before a --textures frame counts the pyramids' levels (a 16384^2
// texture's are 1.4 GiB of float RGBA, which went unestimated: an OOM kill, not a message).
TEST(TextureDetail, PyramidBytesAreTheLevelsHeld) {
  Scene scene;
  scene.textures.push_back(grey_texture(37, 19, [](int x, int) { return float(x); }));
  scene.textures.push_back(grey_texture(8, 8, [](int, int) { return 0.5f; }));  // not a colour's: no pyramid
  Material m;
  m.base_color_texture.index = 0;
  scene.materials.push_back(m);
  const std::vector<TexturePyramid> pyramids = texture_pyramids(scene);
  ASSERT_EQ(pyramids.size(), 2u);
  EXPECT_TRUE(pyramids[1].levels.empty());
  uint64_t held = 0, largest = 0;
  for (const Texture& level : pyramids[0].levels) {
    held += level.texels.size() * sizeof(glm::vec4);
    largest = std::max<uint64_t>(largest, level.texels.size());
  }
  EXPECT_EQ(texture_pyramid_bytes(scene), held + 2 * largest * sizeof(float));
}

// One emissive material whose texture is black but for a white column one texel wide
// (or, given, any other grey texture of 64 x 64).
float stroke(int x, int) { return x == 32 ? 1.0f : 0.0f; }
struct StrokeScene {
  Scene scene;
  std::vector<TexturePyramid> pyramids;
  explicit StrokeScene(float (*value)(int x, int y) = stroke) {
    scene.textures.push_back(grey_texture(64, 64, value));
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

// A base colour texture's miss is weighed by the corners' radiance per unit albedo, the
// albedo taken as at least 0.02: corners on black texels (albedo 0) around a white stroke
// give a finite estimate, corner_mean / 0.02 times what the texture misses.
TEST(TextureDetail, CornersOnBlackTexelsWeighTheirRadianceByAnAlbedoOfAtLeast2Percent) {
  StrokeScene s;
  Material base;
  base.base_color = glm::vec3(1.0f);
  base.base_color_texture.index = 0;
  s.scene.materials[1] = base;
  s.scene.finalize_materials();
  s.pyramids = texture_pyramids(s.scene);
  SurfaceProbe c[4];
  s.corners(28.0f / 64, 37.0f / 64, c);  // all four on black texels
  const glm::vec3 emitted = hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f));
  ASSERT_GT(emitted.r, 0.05f);
  for (SurfaceProbe& p : c) p.material = 1;
  const glm::vec3 lit = hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.01f));
  EXPECT_NEAR(lit.r, (0.01f / 0.02f) * emitted.r, 1e-6f);
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

// Between two levels' sizes the box mean blends them (trilinear, as a GPU's lookup): it
// moves with the footprint's size rather than jumping at the powers of two.
TEST(TextureDetail, ABoxBetweenTwoLevelsSizesBlendsThem) {
  const Texture checker = grey_texture(8, 8, [](int x, int y) { return float((x + y) % 2); });
  const TexturePyramid p(checker);
  // Centred on texel (0, 1) (1 at level 0, 0.5 at level 1), sqrt(2) texels wide: level 0.5.
  const glm::vec2 centre(0.5f / 8, 1.5f / 8), half(std::sqrt(2.0f) / 16);
  EXPECT_NEAR(p.box_mean(checker, centre - half, centre + half).r, 0.75f, 1e-5f);
}

// A dark stroke on white hides as much as a bright one on black: the estimate is
// |box - corners| (the flag judges it downward too: MissedDetail::darker).
TEST(TextureDetail, ADarkStrokeBetweenTheCornersIsFoundToo) {
  const StrokeScene bright, dark([](int x, int) { return x == 32 ? 0.0f : 1.0f; });
  SurfaceProbe c[4];
  bright.corners(28.0f / 64, 37.0f / 64, c);
  const float on_black = hidden_texture_detail(bright.scene, bright.pyramids, c, glm::vec3(0.0f)).r;
  ASSERT_GT(on_black, 0.05f);
  EXPECT_NEAR(hidden_texture_detail(dark.scene, dark.pyramids, c, glm::vec3(1.0f)).r, on_black, 1e-5f);
}

// A base-colour texture's detail is lit as its corners are: their radiance per unit albedo
// (corner mean / (factor x their texel)) times the albedo the corners miss (factor x
// |box - corners|), channel by channel.
TEST(TextureDetail, ABaseColourStrokeIsLitAsItsCorners) {
  StrokeScene s([](int x, int) { return x == 32 ? 0.0f : 1.0f; });
  Material& m = s.scene.materials[0];
  m.emissive = glm::vec3(0.0f);
  m.emissive_texture = TextureRef{};
  m.base_color = glm::vec3(0.25f, 0.5f, 1.0f);
  m.base_color_texture.index = 0;
  s.scene.finalize_materials();
  s.pyramids = texture_pyramids(s.scene);
  SurfaceProbe c[4];
  s.corners(28.0f / 64, 37.0f / 64, c);  // on white texels; the stroke a ninth of the box
  const float light = 2.0f;               // the corners' radiance per unit albedo
  const glm::vec3 hidden = hidden_texture_detail(s.scene, s.pyramids, c, light * m.base_color);
  const float box = s.pyramids[0].box_mean(s.scene.textures[0], {28.0f / 64, 0.4f}, {37.0f / 64, 0.45f}).r;
  ASSERT_LT(box, 0.95f);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(hidden[ch], light * m.base_color[ch] * (1.0f - box), 1e-5f) << ch;
}

// Another material at any one corner is an edge, not detail (not only at the last corner).
TEST(TextureDetail, NoEstimateWhereAnyCornerIsOnAnotherMaterial) {
  const StrokeScene s;
  SurfaceProbe c[4];
  for (int k = 0; k < 4; ++k) {
    s.corners(28.0f / 64, 37.0f / 64, c);
    c[k].material = 1;
    EXPECT_EQ(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)), glm::vec3(0.0f)) << k;
  }
}

// A seam along v is a seam as one along u is: half the texture or more between the
// corners in either direction is no detail.
TEST(TextureDetail, NoEstimateAcrossASeamAlongV) {
  const StrokeScene s;
  SurfaceProbe c[4];
  s.corners(28.0f / 64, 37.0f / 64, c);
  c[0].uv0.y = c[1].uv0.y = 0.05f;
  c[2].uv0.y = c[3].uv0.y = 0.95f;
  EXPECT_EQ(hidden_texture_detail(s.scene, s.pyramids, c, glm::vec3(0.0f)), glm::vec3(0.0f));
}

// The footprint correction's probes for StrokeScene's pixel: one triangle (prim 0), no light.
struct FootprintCorners {
  SurfaceProbe c[4];
  FootprintProbe f[4];
  const FootprintProbe* p[4] = {&f[0], &f[1], &f[2], &f[3]};
  // The correction for these corners; by default a change under 1e-3 settles the 2 x 2 samples.
  FootprintDelta delta(const Scene& scene, glm::vec3 settled = glm::vec3(1e-3f),
                       const FootprintView* view = nullptr) const {
    return texture_footprint_delta(scene, c, p, settled, view);
  }
};

Scene& with_triangle(Scene& scene) {
  scene.positions = {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)};
  return scene;
}

// The correction for corners at u0 .. u1 (by default around the stroke), all on the
// triangle and lit with irradiance 1.
FootprintDelta lit_delta(const StrokeScene& s, float u0 = 30.5f / 64, float u1 = 33.5f / 64) {
  FootprintCorners k;
  s.corners(u0, u1, k.c);
  for (FootprintProbe& f : k.f) f.prim = 0, f.irradiance = glm::vec3(1.0f);
  return k.delta(s.scene);
}

TEST(TextureFootprint, AStrokeBetweenTheCornersIsAveragedIn) {
  StrokeScene s;
  with_triangle(s.scene);
  FootprintCorners k;
  // Corners 3 texels apart on black texels, the stroke's texel between them: the bilinear
  // texture's mean over the footprint is 1/3 (its hat, 2 texels wide, inside the 3).
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  for (FootprintProbe& f : k.f) f.prim = 0;
  const FootprintDelta fine = k.delta(s.scene);
  ASSERT_TRUE(fine.applies);
  EXPECT_NEAR(fine.delta.r, 1.0f / 3.0f, 0.02f);
  // Where the first 2 x 2 estimate could not show, it stays.
  const FootprintDelta coarse = k.delta(s.scene, glm::vec3(1.0f));
  EXPECT_NEAR(coarse.delta.r, 0.375f, 1e-5f);
  // A first estimate that could not show is still refined where two of its four samples
  // differ by `settled` or more. Corners one texel further right: one on the stroke's flank
  // (0.5), so their mean is 0.25; two of the 2 x 2 samples see 0.75, two see 0, so the
  // first estimate adds 0.125 < settled, but its spread is 0.75 >= settled.
  // The texture's mean over the footprint is 0.875 / 3: the delta is 0.042.
  s.corners(32.0f / 64, 35.0f / 64, k.c);
  const FootprintDelta disagreeing = k.delta(s.scene, glm::vec3(0.2f));
  EXPECT_NEAR(disagreeing.delta.r, 0.875f / 3.0f - 0.25f, 0.025f);
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  // Far from the stroke: nothing to add, but the correction applies (no curvature term).
  s.corners(2.0f / 64, 5.0f / 64, k.c);
  const FootprintDelta black = k.delta(s.scene);
  EXPECT_TRUE(black.applies);
  EXPECT_EQ(black.delta, glm::vec3(0.0f));
}

// A metal that also transmits: its transmission is what the metal leaves, transmission x
// (1 - metallic), as whitted_surface takes it; so the diffuse albedo the samples see is the
// corners' own, base x 0.5 x (1 - 0.25) here, and a uniform texture adds exactly nothing.
TEST(TextureFootprint, ATransmittingMetalsSamplesSeeTheCornersAlbedo) {
  StrokeScene s([](int, int) { return 1.0f; });
  with_triangle(s.scene);
  Material& m = s.scene.materials[0];
  m.emissive = glm::vec3(0.0f);
  m.emissive_texture = TextureRef{};
  m.base_color = glm::vec3(0.8f, 0.6f, 0.4f);
  m.metallic = 0.5f;
  m.transmission = 0.5f;
  m.transmission_texture.index = 0;  // R: 1 everywhere
  s.scene.finalize_materials();
  ASSERT_TRUE(m.varies_per_hit());
  const FootprintDelta d = lit_delta(s);
  ASSERT_TRUE(d.applies);
  EXPECT_EQ(d.delta, glm::vec3(0.0f));
}

// A material whose metallic texture (B channel) is 0 but for the stroke's column, lit by a
// light of irradiance 1: the diffuse albedo is base x (1 - metallic), so the stroke darkens
// the pixel by base x the stroke's third of the footprint, and a transmission texture the
// same way scales what the metal leaves. Both go through the lanes' material, not the
// plain albedo's product.
TEST(TextureFootprint, AMetallicOrTransmissionStrokeBetweenTheCornersDarkensTheDiffuse) {
  for (const bool transmission : {false, true}) {
    StrokeScene s;
    with_triangle(s.scene);
    // G (roughness) is the stroke's negative: a read of the wrong channel shows.
    for (glm::vec4& texel : s.scene.textures[0].texels) texel.g = 1.0f - texel.r;
    Material& m = s.scene.materials[0];
    m.emissive = glm::vec3(0.0f);
    m.emissive_texture = TextureRef{};
    m.base_color = glm::vec3(0.8f, 0.6f, 0.4f);
    if (transmission) {
      m.transmission = 1.0f;
      m.transmission_texture.index = 0;  // R: 1 on the stroke
    } else {
      m.metallic = 1.0f;
      m.metallic_roughness_texture.index = 0;  // B: 1 on the stroke
    }
    s.scene.finalize_materials();
    ASSERT_TRUE(m.varies_per_hit());
    const FootprintDelta d = lit_delta(s);
    ASSERT_TRUE(d.applies) << transmission;
    // The corners see no stroke: albedo = base; the pixel a third less of it.
    EXPECT_NEAR(d.delta.r, -0.8f / 3.0f, 0.02f) << transmission;
    EXPECT_NEAR(d.delta.g, -0.6f / 3.0f, 0.02f) << transmission;
    EXPECT_NEAR(d.delta.b, -0.4f / 3.0f, 0.02f) << transmission;
    // Far from the stroke the lanes' albedo is the corners' own: exactly nothing to add.
    const FootprintDelta flat = lit_delta(s, 2.0f / 64, 5.0f / 64);
    EXPECT_TRUE(flat.applies);
    EXPECT_EQ(flat.delta, glm::vec3(0.0f)) << transmission;
  }
}

// Stripes along the pixel's axis, four periods across it: a regular 4 x 4 grid of samples
// sees every stripe at the same phase (delta 1: all its samples on white texel centres);
// the rank-1 lattice has one point in each of its 25 columns, so its mean is the stripes'.
// (The 2 x 2 first estimate sees one phase too, as the corners do: `settled` 0 looks past it.)
TEST(TextureFootprint, StripesAlongThePixelsAxisDoNotAlias) {
  StrokeScene s([](int x, int) { return float(x % 2); });
  with_triangle(s.scene);
  FootprintCorners k;
  s.corners(0.5f / 64, 8.5f / 64, k.c);  // black texel centres 0 and 8: the corners see 0
  for (FootprintProbe& f : k.f) f.prim = 0;
  const FootprintDelta d = k.delta(s.scene, glm::vec3(0.0f));
  ASSERT_TRUE(d.applies);
  // The bilinear stripes' mean over whole periods is 1/2 (the lattice's 25 points: 0.48).
  EXPECT_NEAR(d.delta.r, 0.5f, 0.03f);
}

// A surface folded in the middle of the pixel, seen from the camera at the origin looking
// down -z: flat at depth 1 left of x = 0 (triangle 0), then receding as z = -1 - 2x
// (triangle 1), u running along it. The pixel spans image points x, y in [-0.3, 0.3] at
// depth 1. Across it u is linear left of the fold and convex right of it, and the smooth
// shading normal turns at one rate on each side: no interpolation between the corners
// follows either; with the camera, each sample takes its own triangle's, as the lattice's
// rays would.
struct FoldScene {
  static constexpr float kScale = 0.02f, kSlope = 2.0f;
  Scene scene;
  FoldScene() {
    const glm::vec3 far(10.0f, 0.0f, -1.0f - kSlope * 10.0f);
    // Both wound counter-clockwise as the camera sees them, as their normals face it.
    scene.positions = {glm::vec3(0.0f, -10.0f, -1.0f), glm::vec3(0.0f, 10.0f, -1.0f), glm::vec3(-10.0f, 0.0f, -1.0f),
                       glm::vec3(0.0f, 10.0f, -1.0f), glm::vec3(0.0f, -10.0f, -1.0f), far};
    for (const glm::vec3& p : scene.positions) scene.uvs.push_back(uv_at(p));
    scene.material_of = {0, 0};
    // Smooth across the fold: its edge's vertices take the mean of the two faces' normals.
    const glm::vec3 flat(0.0f, 0.0f, 1.0f), slope = glm::normalize(glm::vec3(kSlope, 0.0f, 1.0f));
    const glm::vec3 edge = glm::normalize(flat + slope);
    scene.normals = {edge, edge, flat, edge, edge, slope};
    scene.tangents.assign(6, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  }
  static glm::vec2 uv_at(glm::vec3 p) {
    const float along = std::sqrt(1.0f + kSlope * kSlope);  // surface length per unit x on the right
    return {0.5f + kScale * (p.x > 0.0f ? p.x * along : p.x), 0.5f + kScale * p.y};
  }
  // Where the ray through image point (x, y) meets the surface, and on which triangle
  // (orthographic: the ray from (x, y, 0) down -z).
  static glm::vec3 hit(float x, float y, bool orthographic = false) {
    if (orthographic) return {x, y, x < 0.0f ? -1.0f : -1.0f - kSlope * x};
    const float t = x < 0.0f ? 1.0f : 1.0f / (1.0f - kSlope * x);
    return {x * t, y * t, -t};
  }
  static int32_t prim(float x) { return x < 0.0f ? 0 : 1; }
  static glm::vec2 image(float s, float t) { return {-0.3f + 0.6f * s, -0.3f + 0.6f * t}; }
  // The barycentrics (of vertices 1 and 2) of point p on triangle `prim`.
  glm::vec2 barycentrics(int32_t prim, glm::vec3 p) const {
    const glm::vec3 a = scene.positions[size_t(prim) * 3], e1 = scene.positions[size_t(prim) * 3 + 1] - a,
                    e2 = scene.positions[size_t(prim) * 3 + 2] - a, d = p - a;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float q1 = glm::dot(d, e1), q2 = glm::dot(d, e2), det = d11 * d22 - d12 * d12;
    return {(d22 * q1 - d12 * q2) / det, (d11 * q2 - d12 * q1) / det};
  }
  glm::vec3 normal(glm::vec3 p) const {
    const int32_t t = prim(p.x);
    const glm::vec2 b = barycentrics(t, p);
    return interpolated_normal(scene, size_t(t) * 3, b.x, b.y, glm::vec3(0.0f, 0.0f, 1.0f));
  }
  // The lattice's mean of f over the pixel (its corner point as the corners' mean) minus
  // the corners' mean, as texture_footprint_delta returns it.
  template <class F>
  static float lattice_delta(F f, bool orthographic = false) {
    double inner = 0.0, corners = 0.0;
    for (int i = 0; i < 4; ++i) {
      const glm::vec2 q = image(float(i % 2), float(i / 2));
      corners += 0.25 * f(hit(q.x, q.y, orthographic));
    }
    for (int p = 1; p < kLatticePoints; ++p) {
      const glm::vec2 q = image(kLattice[size_t(p)].u, kLattice[size_t(p)].v);
      inner += f(hit(q.x, q.y, orthographic)) / double(kLatticePoints - 1);
    }
    return float((inner - corners) * (kLatticePoints - 1) / kLatticePoints);
  }
  void corners(FootprintCorners& k, bool orthographic = false) const {
    for (int i = 0; i < 4; ++i) {
      const glm::vec2 q = image(float(i % 2), float(i / 2));
      k.c[i] = SurfaceProbe{};
      k.c[i].material = 0;
      k.c[i].position = hit(q.x, q.y, orthographic);
      k.c[i].uv0 = uv_at(k.c[i].position);
      k.c[i].normal = normal(k.c[i].position);
      k.c[i].view = orthographic ? glm::vec3(0.0f, 0.0f, 1.0f) : -glm::normalize(k.c[i].position);
      const glm::vec2 b = barycentrics(prim(q.x), k.c[i].position);
      k.f[i] = FootprintProbe{glm::vec3(0.0f), prim(q.x), b.x, b.y, 1.0f};
    }
  }
  static constexpr FootprintView kView{glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
  static constexpr FootprintView kOrthoView{glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, -1.0f), true};
  // The fold's triangles into `textured` (a scene with the material and texture), and the
  // pixel's corners.
  void onto(Scene& textured, FootprintCorners& k, bool orthographic = false) const {
    textured.positions = scene.positions;
    textured.uvs = scene.uvs;
    textured.material_of = scene.material_of;
    corners(k, orthographic);
  }
};

TEST(TextureFootprint, SamplesTakeTheirOwnTriangleAcrossAFold) {
  // An emissive texture whose value is u (bilinear between texel centres).
  StrokeScene s([](int x, int) { return (float(x) + 0.5f) / 64.0f; });
  FootprintCorners k;
  FoldScene().onto(s.scene, k);
  const float expected = FoldScene::lattice_delta([](glm::vec3 p) { return FoldScene::uv_at(p).x; });
  const FootprintDelta exact = k.delta(s.scene, glm::vec3(0.0f), &FoldScene::kView);
  const FootprintDelta interpolated = k.delta(s.scene, glm::vec3(0.0f));
  ASSERT_TRUE(exact.applies);
  ASSERT_TRUE(interpolated.applies);
  EXPECT_NEAR(exact.delta.r, expected, 2e-6f);
  EXPECT_GT(std::abs(interpolated.delta.r - expected), 5e-3f);  // the interpolation sees no delta at all
  std::printf("delta: lattice %.6f, own triangles %.6f, interpolated %.6f\n", expected, exact.delta.r,
              interpolated.delta.r);
}

// The same, the texture's value u + 3v: along the fold's edge v runs with the image's y
// and on the receding triangle the sample's depth scales it, so each sample's two
// barycentrics both count (with the first, u alone, one of them never did).
TEST(TextureFootprint, SamplesTakeTheirOwnTrianglesBothCoordinatesAcrossAFold) {
  StrokeScene s([](int x, int y) { return (float(x) + 0.5f) / 64.0f + 3.0f * (float(y) + 0.5f) / 64.0f; });
  FootprintCorners k;
  FoldScene().onto(s.scene, k);
  const float expected = FoldScene::lattice_delta([](glm::vec3 p) {
    const glm::vec2 uv = FoldScene::uv_at(p);
    return uv.x + 3.0f * uv.y;
  });
  const FootprintDelta exact = k.delta(s.scene, glm::vec3(0.0f), &FoldScene::kView);
  ASSERT_TRUE(exact.applies);
  EXPECT_NEAR(exact.delta.r, expected, 4e-6f);
}

// The same fold, smooth-shaded, normal-mapped (a flat map: the shading normal is the
// interpolated one) and lit by one directional light: each sample is lit at its own
// triangle's normal, as the lattice's rays are.
TEST(TextureFootprint, SamplesAreLitAtTheirOwnTrianglesNormalAcrossAFold) {
  FoldScene fold;
  Scene& scene = fold.scene;
  Texture flat_map;
  flat_map.width = flat_map.height = 4;
  flat_map.texels.assign(16, glm::vec4(0.5f, 0.5f, 1.0f, 1.0f));
  scene.textures.push_back(flat_map);
  Material m;
  m.base_color = glm::vec3(1.0f);
  m.normal_texture.index = 0;
  scene.materials.push_back(m);
  scene.finalize_materials();
  const glm::vec3 to_light = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
  Light light;
  light.type = Light::Type::Directional;
  light.direction = -to_light;
  light.intensity = glm::vec3(2.0f);
  scene.lights.push_back(light);
  const float albedo = scene.whitted[0].diffuse.r;
  auto lambert = [&](glm::vec3 p) {
    return albedo * 2.0f / float(M_PI) * std::max(glm::dot(fold.normal(p), to_light), 0.0f);
  };
  FootprintCorners k;
  fold.corners(k);
  for (int i = 0; i < 4; ++i) k.f[i].irradiance = glm::vec3(lambert(k.c[i].position) / albedo);
  const float expected = FoldScene::lattice_delta(lambert);
  const FootprintDelta exact = k.delta(scene, glm::vec3(0.0f), &FoldScene::kView);
  const FootprintDelta interpolated = k.delta(scene, glm::vec3(0.0f));
  ASSERT_TRUE(exact.applies);
  ASSERT_GT(std::abs(expected), 1e-3f);
  EXPECT_NEAR(exact.delta.r, expected, 1e-3f * std::abs(expected));
  EXPECT_GT(std::abs(interpolated.delta.r - expected), 0.1f * std::abs(expected));
  std::printf("lit delta: lattice %.6f, own triangles %.6f, interpolated %.6f\n", expected, exact.delta.r,
              interpolated.delta.r);
}

// The same fold under an orthographic camera on the plane z = 0 (its rays run down -z
// from the image points): each sample's ray starts at its own point of the plane.
TEST(TextureFootprint, SamplesTakeTheirOwnTriangleUnderAnOrthographicCamera) {
  StrokeScene s([](int x, int) { return (float(x) + 0.5f) / 64.0f; });
  FootprintCorners k;
  FoldScene().onto(s.scene, k, /*orthographic=*/true);
  const float expected =
      FoldScene::lattice_delta([](glm::vec3 p) { return FoldScene::uv_at(p).x; }, /*orthographic=*/true);
  const FootprintDelta exact = k.delta(s.scene, glm::vec3(0.0f), &FoldScene::kOrthoView);
  ASSERT_TRUE(exact.applies);
  ASSERT_GT(std::abs(expected), 1e-3f);
  EXPECT_NEAR(exact.delta.r, expected, 2e-6f);
}

// Which of the corners' triangles a sample falls in does not depend on the order of their
// vertices: with the receding triangle's shared edge its second and third vertices, the
// samples left of the fold meet its plane nearer than their own triangle, beyond that
// edge (u + v > 1), and must not take it.
TEST(TextureFootprint, SamplesTakeTheirOwnTriangleWhateverItsVertexOrder) {
  StrokeScene s([](int x, int) { return (float(x) + 0.5f) / 64.0f; });
  FoldScene fold;
  std::rotate(fold.scene.positions.begin() + 3, fold.scene.positions.begin() + 5, fold.scene.positions.end());
  std::rotate(fold.scene.normals.begin() + 3, fold.scene.normals.begin() + 5, fold.scene.normals.end());
  std::rotate(fold.scene.uvs.begin() + 3, fold.scene.uvs.begin() + 5, fold.scene.uvs.end());
  FootprintCorners k;
  fold.onto(s.scene, k);
  const float expected = FoldScene::lattice_delta([](glm::vec3 p) { return FoldScene::uv_at(p).x; });
  const FootprintDelta exact = k.delta(s.scene, glm::vec3(0.0f), &FoldScene::kView);
  ASSERT_TRUE(exact.applies);
  EXPECT_NEAR(exact.delta.r, expected, 2e-6f);
}

TEST(TextureFootprint, NotAcrossMaterialsSeamsAtlasJumpsOrMisses) {
  StrokeScene s;
  with_triangle(s.scene);
  FootprintCorners k;
  auto applies = [&] { return k.delta(s.scene).applies; };
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  for (FootprintProbe& f : k.f) f.prim = 0;
  ASSERT_TRUE(applies());
  k.c[3].material = 1;  // an edge between materials
  EXPECT_FALSE(applies());
  s.corners(0.05f, 0.95f, k.c);  // a UV seam
  EXPECT_FALSE(applies());
  s.corners(0.2f, 0.5f, k.c);  // an atlas jump: 19 texels between neighbouring corners
  EXPECT_FALSE(applies());
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  k.c[3].uv0 += glm::vec2(4.0f / 64, 0.0f);  // not one smooth patch: the quad is twisted
  EXPECT_FALSE(applies());
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  k.f[2].prim = -1;  // a miss
  EXPECT_FALSE(applies());
}

// A white diffuse plane z = 0 (normal +z, tangent +x) lit by a directional light from
// (1, 0, 1), under a normal map that is flat but for column 32, whose normal faces the light.
struct BumpScene {
  Scene scene;
  static constexpr float kIntensity = 2.0f;
  const glm::vec3 to_light = glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f));
  BumpScene() {
    const glm::vec3 tilted = to_light * 0.5f + 0.5f;
    Texture t;
    t.width = t.height = 64;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) t.texels.push_back(x == 32 ? glm::vec4(tilted, 1.0f) : glm::vec4(0.5f, 0.5f, 1.0f, 1.0f));
    scene.textures.push_back(t);
    Material m;
    m.base_color = glm::vec3(1.0f);
    m.metallic = 0.0f;
    m.normal_texture.index = 0;
    scene.materials.push_back(m);
    scene.finalize_materials();
    with_triangle(scene);
    scene.normals.assign(3, glm::vec3(0.0f, 0.0f, 1.0f));
    scene.tangents.assign(3, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    Light light;
    light.type = Light::Type::Directional;
    light.direction = -to_light;
    light.intensity = glm::vec3(kIntensity);
    scene.lights.push_back(light);
  }
  // The lit Lambert radiance per unit albedo at normal n.
  float lambert(glm::vec3 n) const { return kIntensity / float(M_PI) * std::max(glm::dot(n, to_light), 0.0f); }
  void corners(float u0, float u1, FootprintCorners& k) const {
    const float us[4] = {u0, u1, u0, u1}, vs[4] = {0.4f, 0.4f, 0.45f, 0.45f};
    for (int i = 0; i < 4; ++i) {
      k.c[i] = SurfaceProbe{};
      k.c[i].material = 0;
      k.c[i].uv0 = k.c[i].uv1 = {us[i], vs[i]};
      k.c[i].position = glm::vec3(0.1f, 0.1f, 0.0f);
      k.c[i].normal = glm::vec3(0.0f, 0.0f, 1.0f);
      k.c[i].view = glm::vec3(0.0f, 0.0f, 1.0f);
      k.c[i].shininess = 1.0f;  // no highlight: specular 0
      k.f[i] = FootprintProbe{glm::vec3(lambert(k.c[i].normal)), 0, 0.1f, 0.1f, 1.0f};
    }
  }
};

TEST(TextureFootprint, ANormalMapBumpBetweenTheCornersIsLitAtItsNormal) {
  const BumpScene s;
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k);
  const FootprintDelta d = k.delta(s.scene);
  ASSERT_TRUE(d.applies);
  // The same mean by brute force: the bilinear normal map at 64 x 64 points of the footprint.
  double mean = 0.0;
  const Texture& map = s.scene.textures[0];
  for (int i = 0; i < 64; ++i) {
    const float u = (30.5f + 3.0f * (float(i) + 0.5f) / 64.0f) / 64.0f;
    const glm::vec3 n = glm::normalize(glm::vec3(map.sample({u, 0.42f})) * 2.0f - 1.0f);
    mean += s.lambert(n) / 64.0;
  }
  const float expected = float(mean) - s.lambert(glm::vec3(0.0f, 0.0f, 1.0f));
  ASSERT_GT(expected, 0.02f);
  EXPECT_NEAR(d.delta.r, expected, 0.1f * expected);
  // A corner lit more than its recorded light says (a partial shadow): only the albedo
  // varies, and it does not here.
  k.f[1].irradiance *= 0.5f;
  const FootprintDelta shadowed = k.delta(s.scene);
  EXPECT_TRUE(shadowed.applies);
  EXPECT_NEAR(shadowed.delta.r, 0.0f, 1e-6f);
}

// Away from the bump, on a shiny surface, the samples' model is the corners' own, the
// highlight included: a flat stretch of the map adds exactly nothing.
TEST(TextureFootprint, AFlatStretchOfAShinyNormalMapAddsNothing) {
  const BumpScene s;
  FootprintCorners k;
  s.corners(2.0f / 64, 5.0f / 64, k);
  for (SurfaceProbe& c : k.c) c.specular = glm::vec3(0.5f), c.shininess = 8.0f;
  const FootprintDelta d = k.delta(s.scene);
  ASSERT_TRUE(d.applies);
  EXPECT_NEAR(d.delta.r, 0.0f, 1e-6f);
}

// Seen from behind the triangle (side -1), the map applies in the frame turned over, as
// the shader's: the mirror image of the front's case, lit from the mirrored side, gets
// the front's delta.
TEST(TextureFootprint, ANormalMapSeenFromBehindIsInTheTurnedFrame) {
  const BumpScene front;
  FootprintCorners k;
  front.corners(30.5f / 64, 33.5f / 64, k);
  const FootprintDelta d = k.delta(front.scene);
  ASSERT_GT(d.delta.r, 0.02f);
  BumpScene back;
  // The bump's normal (its frame's t + n) turned over: towards -x, -z.
  back.scene.lights[0].direction = glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f));
  for (int i = 0; i < 4; ++i) {
    k.c[i].normal = k.c[i].view = glm::vec3(0.0f, 0.0f, -1.0f);
    k.f[i].side = -1.0f;
  }
  const FootprintDelta behind = k.delta(back.scene);
  ASSERT_TRUE(behind.applies);
  EXPECT_NEAR(behind.delta.r, d.delta.r, 1e-5f);
}

// A light in shadow at all four corners (its bit in `blocked`, not in their irradiance)
// is left out; the others are still lit light by light.
TEST(TextureFootprint, ALightShadowedAtEveryCornerIsLeftOut) {
  BumpScene s;
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k);
  const FootprintDelta one = k.delta(s.scene);
  ASSERT_GT(one.delta.r, 0.02f);
  Light shadowed = s.scene.lights[0];
  shadowed.direction = glm::normalize(glm::vec3(1.0f, 0.0f, -1.0f));  // from -x, above the plane
  s.scene.lights.push_back(shadowed);
  for (SurfaceProbe& c : k.c) c.blocked = 1u << 1;
  const FootprintDelta two = k.delta(s.scene);
  ASSERT_TRUE(two.applies);
  EXPECT_NEAR(two.delta.r, one.delta.r, 1e-6f);
}

// A corner a little short of its light (a partial shadow: 5 %, past the 2 % the float
// sums may miss by) is not lit light by light either; one within 1 % still is.
TEST(TextureFootprint, ACornerShortOfItsLightIsNotLitLightByLight) {
  const BumpScene s;
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k);
  const FootprintDelta lit = k.delta(s.scene);
  ASSERT_GT(lit.delta.r, 0.02f);
  const glm::vec3 irradiance = k.f[1].irradiance;
  k.f[1].irradiance = 0.99f * irradiance;
  EXPECT_NEAR(k.delta(s.scene).delta.r, lit.delta.r, 1e-6f);
  k.f[1].irradiance = 0.95f * irradiance;
  EXPECT_NEAR(k.delta(s.scene).delta.r, 0.0f, 1e-6f);
}

// Up to kFootprintLights lights are lit one by one: the bump's light split in that many
// gives its delta; one more light, and only the albedo varies (not at all here).
TEST(TextureFootprint, UpToKFootprintLightsAreLitOneByOne) {
  BumpScene s;
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k);
  const FootprintDelta one = k.delta(s.scene);
  ASSERT_GT(one.delta.r, 0.02f);
  Light part = s.scene.lights[0];
  part.intensity /= float(kFootprintLights);
  s.scene.lights.assign(size_t(kFootprintLights), part);
  const FootprintDelta split = k.delta(s.scene);
  EXPECT_NEAR(split.delta.r, one.delta.r, 1e-4f * one.delta.r);
  part.intensity = glm::vec3(0.0f);
  s.scene.lights.push_back(part);  // one more, dark: the irradiance is the same
  EXPECT_NEAR(k.delta(s.scene).delta.r, 0.0f, 1e-6f);
}

// A corner whose shading normal is not its map's (the shader fell back to the geometric
// normal where the map's faced away) is not lit light by light: only the albedo varies,
// and it does not here.
TEST(TextureFootprint, ACornerShadedAtAnotherNormalThanItsMapsIsNotLitLightByLight) {
  const BumpScene s;
  FootprintCorners k;
  s.corners(2.0f / 64, 5.0f / 64, k);  // the flat map: +z
  const glm::vec3 other = glm::normalize(glm::vec3(0.2f, 0.0f, 1.0f));
  for (int i = 0; i < 4; ++i) {
    k.c[i].normal = other;
    k.f[i].irradiance = glm::vec3(s.lambert(other));
  }
  const FootprintDelta d = k.delta(s.scene);
  ASSERT_TRUE(d.applies);
  EXPECT_NEAR(d.delta.r, 0.0f, 1e-6f);
}

// A sample whose normal faces away from a light gets none of it (not negative light):
// the bump turned away from the light darkens the pixel by what the brute-force mean of
// Lambert's max(cos, 0) says.
TEST(TextureFootprint, ABumpFacingAwayFromTheLightGetsNoneOfIt) {
  BumpScene s;
  const glm::vec3 away = glm::normalize(glm::vec3(-1.0f, 0.0f, 0.1f));
  Texture& map = s.scene.textures[0];
  for (int y = 0; y < 64; ++y) map.texels[size_t(y) * 64 + 32] = glm::vec4(away * 0.5f + 0.5f, 1.0f);
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k);
  const FootprintDelta d = k.delta(s.scene);
  ASSERT_TRUE(d.applies);
  double mean = 0.0;
  for (int i = 0; i < 64; ++i) {
    const float u = (30.5f + 3.0f * (float(i) + 0.5f) / 64.0f) / 64.0f;
    const glm::vec3 n = glm::normalize(glm::vec3(map.sample({u, 0.42f})) * 2.0f - 1.0f);
    mean += s.lambert(n) / 64.0;
  }
  const float expected = float(mean) - s.lambert(glm::vec3(0.0f, 0.0f, 1.0f));
  ASSERT_LT(expected, -0.02f);
  EXPECT_NEAR(d.delta.r, expected, 0.1f * std::abs(expected));
}

// A twist of the corners' coordinates up to half the longer edge is still one patch; more
// is not (a 2-texel twist on edges of 3 and 3.2 texels).
TEST(TextureFootprint, ATwistOfMoreThanHalfAnEdgeIsNotOnePatch) {
  StrokeScene s;
  with_triangle(s.scene);
  FootprintCorners k;
  for (FootprintProbe& f : k.f) f.prim = 0;
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  k.c[3].uv0 += glm::vec2(1.0f / 64, 0.0f);
  EXPECT_TRUE(k.delta(s.scene).applies);
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  k.c[3].uv0 += glm::vec2(2.0f / 64, 0.0f);
  EXPECT_FALSE(k.delta(s.scene).applies);
}

// The footprint of what a mirror shows, through SceneSource (render/scene_source.h): the
// corners' probes put at node 1 of the path tree (the camera ray's reflection), its path
// weighed by weight[i] at corner i; the camera at the origin looking down -z. `k`: the
// corners as texture_footprint_delta takes them.
float4 reflected_footprint(Scene& scene, const FootprintCorners& k, const glm::vec3 weight[4], float4 mean) {
  scene.cameras.assign(1, Camera{});
  scene.cameras[0].position = glm::vec3(0.0f);
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const CameraRays camera(scene.cameras[0], 40, 40);
  HiddenDetail detail;
  detail.footprint = true;
  const SceneSource source(shader, camera, kSignatureNone, &detail);
  SceneSource::Probe grid[16];  // a 4 x 4 stencil, the pixel's corners at 5, 6, 9, 10
  const int at[4] = {5, 6, 9, 10};
  SceneSource::FootprintCorner prepared[4];
  for (int i = 0; i < 4; ++i) {
    SceneSource::Probe& p = grid[at[i]];
    p.node[probe_slot(kFootprintNode[1])] = k.c[i];
    p.footprint[1] = k.f[i];
    p.footprint[1].weight = weight[i];
    prepared[i] = source.footprint_corner(p);
  }
  const SceneSource::FootprintCorner* const four[4] = {&prepared[0], &prepared[1], &prepared[2], &prepared[3]};
  return source.footprint_delta(grid + 5, 4, four, mean);
}

// What a mirror of reflectance w shows adds w times its own delta, the display step it
// is settled at divided by w (a step at the camera is 1/w of one at the mirror's image):
// at a tiny w the 2 x 2 first estimate settles it, at w = 1/2 it is refined.
TEST(TextureFootprint, AMirrorsImageAddsItsDeltaTimesTheMirrorsWeight) {
  StrokeScene s;
  with_triangle(s.scene);
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  for (FootprintProbe& f : k.f) f.prim = 0;
  const float4 mean(0.5f, 0.5f, 0.5f, 0.0f);
  const float settled = (float4(kFootprintSettledSteps / 255.0f) / ToneMap{}.slope4(mean))[0];
  for (const float w : {0.5f, 1e-3f}) {
    const glm::vec3 weight[4] = {glm::vec3(w), glm::vec3(w), glm::vec3(w), glm::vec3(w)};
    const float4 d = reflected_footprint(s.scene, k, weight, mean);
    const float own = k.delta(s.scene, glm::vec3(settled / w)).delta.r;
    EXPECT_EQ(d[3], 1.0f) << w;
    EXPECT_NEAR(d[0], w * own, 1e-6f * w) << w;
  }
  // The case: at the tiny weight, the step at the camera and at the mirror's image settle
  // the pixel differently.
  EXPECT_GT(std::abs(k.delta(s.scene, glm::vec3(settled / 1e-3f)).delta.r -
                     k.delta(s.scene, glm::vec3(settled)).delta.r),
            0.01f);
}

// A mirror whose weight differs across the corners by more than a quarter (a pixel over
// the edge of a tinted stripe) is no even weight over the pixel: no delta; within a
// quarter it applies.
TEST(TextureFootprint, AMirrorsImageOnlyUnderAnEvenWeight) {
  StrokeScene s;
  with_triangle(s.scene);
  FootprintCorners k;
  s.corners(30.5f / 64, 33.5f / 64, k.c);
  for (FootprintProbe& f : k.f) f.prim = 0;
  const float4 mean(0.5f, 0.5f, 0.5f, 0.0f);
  glm::vec3 weight[4] = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(0.8f)};
  EXPECT_EQ(reflected_footprint(s.scene, k, weight, mean)[3], 1.0f);
  weight[3] = glm::vec3(1.0f, 1.0f, 0.5f);  // uneven in blue alone
  const float4 uneven = reflected_footprint(s.scene, k, weight, mean);
  EXPECT_EQ(uneven[3], 0.0f);
  EXPECT_EQ(uneven[0], 0.0f);
}

// The camera's rays reach only the primary hit: what a mirror shows across FoldScene's
// fold keeps the corners' interpolation (the camera at the fold's would cast rays that
// meet the fold itself, not its image, and find their own triangles).
TEST(TextureFootprint, AMirrorsImageIsNotRecastFromTheCamera) {
  StrokeScene s([](int x, int) { return (float(x) + 0.5f) / 64.0f; });
  FootprintCorners k;
  FoldScene().onto(s.scene, k);
  const glm::vec3 weight[4] = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f)};
  const float4 d = reflected_footprint(s.scene, k, weight, float4(0.5f, 0.5f, 0.5f, 0.0f));
  const float interpolated = k.delta(s.scene, glm::vec3(0.0f)).delta.r;
  const float recast = k.delta(s.scene, glm::vec3(0.0f), &FoldScene::kView).delta.r;
  ASSERT_GT(std::abs(recast - interpolated), 5e-3f);
  EXPECT_EQ(d[3], 1.0f);
  EXPECT_NEAR(d[0], interpolated, 1e-6f);
}

// glTF's tangent w of -1 (a mirrored UV layout) turns the normal map's bitangent over.
TEST(NormalMap, ANegativeHandednessTurnsTheBitangentOver) {
  Scene scene;
  with_triangle(scene);
  scene.normals.assign(3, glm::vec3(0.0f, 0.0f, 1.0f));
  glm::vec3 frame[3];
  for (const float w : {1.0f, -1.0f}) {
    scene.tangents.assign(3, glm::vec4(1.0f, 0.0f, 0.0f, w));
    ASSERT_TRUE(normal_map_frame(scene, 0, 0.2f, 0.3f, glm::vec3(0.0f, 0.0f, 1.0f), frame));
    EXPECT_LT(glm::distance(frame[0], glm::vec3(1.0f, 0.0f, 0.0f)), 1e-6f) << w;
    EXPECT_LT(glm::distance(frame[1], glm::vec3(0.0f, w, 0.0f)), 1e-6f) << w;
  }
}

// normalTexture.scale scales the texel's x and y, not z (glTF).
TEST(NormalMap, TheScaleScalesXAndYOnly) {
  const glm::vec3 frame[3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  const glm::vec3 n = mapped_in_frame(frame, glm::vec3(0.8f, 0.5f, 0.9f), 0.5f, frame[2]);  // texel (0.6, 0, 0.8)
  EXPECT_LT(glm::distance(n, glm::normalize(glm::vec3(0.3f, 0.0f, 0.8f))), 1e-6f);
}

// At the loader's limit on the scale (kNormalScaleLimit) a tilted texel's normal lies in the
// tangent plane, as glTF's formula gives for any larger scale, not the fallback.
TEST(NormalMap, AtTheScalesLimitATiltedTexelLiesInTheTangentPlane) {
  const glm::vec3 frame[3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  const glm::vec3 fallback(0.0f, 0.0f, 1.0f);
  EXPECT_LT(glm::distance(mapped_in_frame(frame, glm::vec3(0.8f, 0.5f, 0.9f), kNormalScaleLimit, fallback),
                          glm::vec3(1.0f, 0.0f, 0.0f)), 1e-6f);
  EXPECT_LT(glm::distance(mapped_in_frame(frame, glm::vec3(0.2f, 0.5f, 0.9f), -kNormalScaleLimit, fallback),
                          glm::vec3(1.0f, 0.0f, 0.0f)), 1e-6f);
  // Past about 1e19 its length overflows: why the loader holds the scale there.
  EXPECT_EQ(mapped_in_frame(frame, glm::vec3(0.8f, 0.5f, 0.9f), 1e20f, fallback), fallback);
}

}  // namespace
}  // namespace zz
