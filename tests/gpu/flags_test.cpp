// The compute shader's flags equal a CPU implementation of the rule bit for bit, and
// the result does not depend on how the frame is split into tiles.
#include <gtest/gtest.h>

#include <cstdio>

#include "flag_reference.h"
#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_busy_scene.h"

namespace zz::test {
namespace {

using FlagsTest = GpuTest;

void expect_matches_reference(VulkanContext& context, const Scene& scene, const Camera& camera, int w, int h,
                              const VisibilitySettings& settings) {
  VisibilityPass pass(context, scene);
  GeoMap gpu = pass.run(camera, w, h, settings);
  std::vector<uint32_t> ids = pass.render_ids(camera, w, h, settings);
  std::vector<glm::vec4> normals = geometric_normals(scene);
  FlagReference ref{ids, scene.positions, normals, make_flag_push(camera, w, h, settings)};
  GeoMap cpu = ref.map();
  ASSERT_EQ(gpu.width, w);
  ASSERT_EQ(gpu.height, h);
  ASSERT_EQ(gpu.flags.size(), cpu.flags.size());
  size_t diff = 0;
  for (size_t i = 0; i < cpu.flags.size(); ++i) diff += gpu.flags[i] != cpu.flags[i];
  EXPECT_EQ(diff, 0u) << "of " << cpu.flags.size() << " pixels";
  size_t n = flagged(cpu);
  // A meaningful comparison: some pixels flagged, most not.
  EXPECT_GT(n, size_t(w + h)) << "too few flags to compare";
  EXPECT_LT(n, cpu.flags.size() / 2);
}

TEST_F(FlagsTest, ShaderMatchesCpuRuleS4) {
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  expect_matches_reference(context(), busy_scene(), camera, 96, 72, VisibilitySettings{});
}

TEST_F(FlagsTest, ShaderMatchesCpuRuleS6OddSizeTightThresholds) {
  Camera camera = Camera::look_at({-1.2f, 0.3f, 2.2f}, {0.1f, 0.0f, -0.3f}, {0, 1, 0}, 0.9f);
  VisibilitySettings s;
  s.supersample = 6;
  s.normal_angle_deg = 5.0f;
  s.depth_rel = 0.002f;
  expect_matches_reference(context(), busy_scene(), camera, 53, 41, s);
}

TEST_F(FlagsTest, ShaderMatchesCpuRuleInBands) {
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilitySettings s;
  s.max_tile_dim = 4 * 8 + 2;  // 8-pixel tiles
  expect_matches_reference(context(), busy_scene(), camera, 45, 30, s);
}

// A scene of more triangles than one dispatch of the planes pass may hold (a device's
// maxComputeWorkGroupCount, 4.2 M triangles on lavapipe) takes several, each from its own
// first triangle: here 64 triangles a dispatch.
TEST_F(FlagsTest, ShaderMatchesCpuRuleWithThePlanesInManyDispatches) {
  const Scene scene = busy_scene();
  ASSERT_GT(scene.positions.size() / 3, size_t(4 * ZZ_PLANE_GROUP));
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilitySettings s;
  s.max_plane_groups = 1;
  expect_matches_reference(context(), scene, camera, 96, 72, s);
}

TEST_F(FlagsTest, BandingDoesNotChangeTheResult) {
  Scene scene = busy_scene();
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  for (int ss : {4, 6}) {
    VisibilitySettings whole;
    whole.supersample = ss;
    VisibilityTimings t_whole, t_tiles, t_bands;
    GeoMap a = pass.run(camera, 101, 67, whole, &t_whole);
    std::vector<uint32_t> ids_a = pass.render_ids(camera, 101, 67, whole);
    VisibilitySettings tiles = whole;
    tiles.max_tile_dim = 12 * ss + 2;      // 12 x 12 pixel tiles, widths multiple of 4
    VisibilitySettings bands = whole;
    bands.max_tile_samples = int64_t(101 * ss + 2) * (7 * ss + 2);  // 7-row bands
    GeoMap b = pass.run(camera, 101, 67, tiles, &t_tiles);
    GeoMap c = pass.run(camera, 101, 67, bands, &t_bands);
    EXPECT_EQ(t_whole.tiles, 1);
    EXPECT_GT(t_tiles.tiles, 40);
    EXPECT_EQ(t_bands.tiles, 10);
    EXPECT_EQ(a.flags, b.flags) << "S=" << ss;
    EXPECT_EQ(a.flags, c.flags) << "S=" << ss;
    // Tiles change the float viewport transform, so edge samples may snap differently
    // (fixed-point rasterisation); only a few, and never enough to change a flag.
    std::vector<uint32_t> ids_b = pass.render_ids(camera, 101, 67, tiles);
    ASSERT_EQ(ids_a.size(), ids_b.size());
    size_t id_diff = 0;
    for (size_t i = 0; i < ids_a.size(); ++i) id_diff += ids_a[i] != ids_b[i];
    std::printf("S=%d: %zu of %zu ids differ between 1 tile and %d tiles\n", ss, id_diff, ids_a.size(),
                t_tiles.tiles);
    EXPECT_LE(id_diff, ids_a.size() / 2000);
    EXPECT_GT(flagged(a), 100u);
  }
}

TEST_F(FlagsTest, RepeatedRunsAreDeterministicAndTimed) {
  Scene scene = busy_scene();
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  VisibilityTimings t;
  GeoMap a = pass.run(camera, 64, 64, {}, &t);
  GeoMap b = pass.run(camera, 64, 64, {});
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_GT(t.total_s, 0.0);
  EXPECT_LT(t.total_s, 30.0);
  EXPECT_EQ(t.tiles, 1);
  // The one-off upload is the constructor's, reported with every frame.
  EXPECT_GT(t.upload_s, 0.0);
  EXPECT_EQ(t.upload_s, pass.upload_seconds());
  EXPECT_GE(t.readback_s, 0.0);
  EXPECT_LE(t.readback_s, t.total_s);
  if (context().timestamps()) {  // GPU timestamps: both passes did run and took time
    EXPECT_GT(t.raster_s, 0.0);
    EXPECT_GT(t.compute_s, 0.0);
  } else {
    EXPECT_EQ(t.raster_s, 0.0);
    EXPECT_EQ(t.compute_s, 0.0);
  }
  EXPECT_LE(t.raster_s + t.compute_s, t.total_s * 1.5 + 1e-3);
}

// (Untiled at S = 4 and 6: GeoFlagsCpuTest.MatchesReferenceAndShaderWithTheMaterialRule.)
TEST_F(FlagsTest, ShaderMatchesCpuRuleWithTheMaterialRuleInTiles) {
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilitySettings s;
  s.material_edges = true;
  s.supersample = 6;
  s.max_tile_dim = 6 * 16 + 2;  // 16-pixel tiles: the rule is the same across tile seams
  expect_matches_reference(context(), busy_checker_scene(), camera, 53, 41, s);
}

// The material rule adds exactly the pixels whose own samples (not the ring) fall on two
// materials: a coplanar checker's boundaries, which the geometric rule cannot see. On a
// scene of one material it changes nothing.
TEST_F(FlagsTest, TheMaterialRuleFlagsPixelsWhoseOwnSamplesSeeTwoMaterials) {
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  const int w = 80, h = 60, S = 4;
  VisibilitySettings off, on;
  on.material_edges = true;
  const Scene checker = busy_checker_scene();
  VisibilityPass pass(context(), checker);
  const GeoMap a = pass.run(camera, w, h, off), b = pass.run(camera, w, h, on);
  const std::vector<uint32_t> ids = pass.render_ids(camera, w, h, on);
  const std::vector<glm::vec4> normals = geometric_normals(checker);
  size_t added = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      ASSERT_TRUE(!a.flags[i] || b.flags[i]) << x << "," << y;
      if (a.flags[i] || !b.flags[i]) continue;
      ++added;
      bool two = false;  // two materials among the pixel's S x S samples
      float first = -1.0f;
      for (int j = 0; j < S; ++j)
        for (int k = 0; k < S; ++k) {
          const uint32_t id = ids[size_t(y * S + j + 1) * (w * S + 2) + size_t(x * S + k + 1)];
          ASSERT_NE(id, 0u);  // added flags lie on the floor, never at a silhouette
          const float tag = normals[id - 1].w;
          if (first < 0.0f) first = tag;
          two = two || tag != first;
        }
      EXPECT_TRUE(two) << "pixel " << x << "," << y << " flagged by its ring alone";
    }
  EXPECT_GT(added, size_t(w));  // the checker's boundaries cross the view

  VisibilityPass plain(context(), busy_scene());
  EXPECT_EQ(plain.run(camera, w, h, off).flags, plain.run(camera, w, h, on).flags);
}

// The material rule compares material_tag: the index itself (exact in a float) below 2^24,
// so materials 2^23 apart stay apart; only indices 2^24 apart share a tag. A triangle
// without a material entry has tag 0. Mutation testing: the modulus 2^23 changed no test.
TEST(MaterialTag, IsTheMaterialIndexModulo2To24) {
  Scene scene;
  scene.material_of = {0u, 1u << 23, 5u, (1u << 24) + 5u, (1u << 24) - 1u};
  EXPECT_EQ(material_tag(scene, 0), 0.0f);
  EXPECT_EQ(material_tag(scene, 1), 8388608.0f);
  EXPECT_EQ(material_tag(scene, 2), 5.0f);
  EXPECT_EQ(material_tag(scene, 3), 5.0f);
  EXPECT_EQ(material_tag(scene, 4), 16777215.0f);
  EXPECT_EQ(material_tag(scene, 5), 0.0f);
}

}  // namespace
}  // namespace zz::test
