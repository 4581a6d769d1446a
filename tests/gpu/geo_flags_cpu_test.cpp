// The host SSE flag rule equals the scalar reference and the compute shader bit for bit.
#include <gtest/gtest.h>

#include "core/error.h"
#include "flag_reference.h"
#include "gpu/geo_flags_cpu.h"
#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_busy_scene.h"

namespace zz::test {
namespace {

using GeoFlagsCpuTest = GpuTest;

void expect_all_agree(VulkanContext& context, const Camera& camera, int w, int h, const VisibilitySettings& s,
                      const Scene& scene = busy_scene()) {
  VisibilityPass pass(context, scene);
  const GeoMap gpu = pass.run(camera, w, h, s);
  const std::vector<uint32_t> ids = pass.render_ids(camera, w, h, s);
  const std::vector<glm::vec4> normals = geometric_normals(scene);
  const gpu::FlagPush push = make_flag_push(camera, w, h, s);
  const GeoMap reference = FlagReference{ids, scene.positions, normals, push}.map();
  const GeoMap sse = geo_flags_cpu(ids, triangle_planes(scene.positions, normals, glm::vec3(push.origin)), push,
                                   &normals);
  ASSERT_EQ(sse.width, w);
  ASSERT_EQ(sse.height, h);
  EXPECT_EQ(sse.flags, reference.flags);
  EXPECT_EQ(sse.flags, gpu.flags);
  EXPECT_GT(flagged(sse), size_t(w + h));
  EXPECT_LT(flagged(sse), sse.flags.size() / 2);
}

TEST_F(GeoFlagsCpuTest, MatchesReferenceAndShaderS4) {
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  expect_all_agree(context(), camera, 96, 72, {});
}

TEST_F(GeoFlagsCpuTest, MatchesReferenceAndShaderS6OddSizeTightThresholds) {
  const Camera camera = Camera::look_at({-1.2f, 0.3f, 2.2f}, {0.1f, 0.0f, -0.3f}, {0, 1, 0}, 0.9f);
  VisibilitySettings s;
  s.supersample = 6;
  s.normal_angle_deg = 5.0f;
  s.depth_rel = 0.002f;
  expect_all_agree(context(), camera, 53, 41, s);
}

TEST_F(GeoFlagsCpuTest, MatchesReferenceAndShaderS12) {
  // S = 12: register rows of 50 ids, masks up to 13 bits.
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilitySettings s;
  s.supersample = 12;
  expect_all_agree(context(), camera, 37, 29, s);
}

TEST_F(GeoFlagsCpuTest, MatchesReferenceAndShaderWithTheMaterialRule) {
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilitySettings s;
  s.material_edges = true;
  expect_all_agree(context(), camera, 96, 72, s, busy_checker_scene());
  s.supersample = 6;
  expect_all_agree(context(), camera, 53, 41, s, busy_checker_scene());
}

TEST(GeoFlagsCpu, TheMaterialRuleNeedsTheNormals) {
  gpu::FlagPush p{};
  p.frame = glm::ivec4(1, 1, 1, 1);
  p.limits = glm::vec4(0.9f, 0.02f, 1.0f, 0.0f);
  EXPECT_THROW(geo_flags_cpu(std::vector<uint32_t>(9, 0), {}, p), Error);
}

}  // namespace
}  // namespace zz::test
