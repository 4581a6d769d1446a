// The host SSE flag rule equals the scalar reference and the compute shader bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>

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

// An orthographic camera steps the rays' origins, not their directions (limits.w): the
// shader, the reference and the SSE rule intersect each plane with the same ray.
TEST_F(GeoFlagsCpuTest, MatchesReferenceAndShaderOrthographic) {
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  camera.ymag = 0.9f;
  ASSERT_EQ(make_flag_push(camera, 96, 72, {}).limits.w, 1.0f);
  expect_all_agree(context(), camera, 96, 72, {});
  VisibilitySettings s;
  s.supersample = 6;
  s.normal_angle_deg = 5.0f;
  s.depth_rel = 0.002f;
  s.material_edges = true;
  expect_all_agree(context(), camera, 53, 41, s, busy_checker_scene());
}

// S = 5 (and 10, 15): pair midpoints and sample rows fall on zone boundaries (u = 0.2,
// 0.4, ...), where a zone bit names both neighbouring zones (the second line of zone_at in
// the shader, map_zone_at on the host). At S = 4, 6 and 12 no pair lies on one. Mutation
// testing: the shader's boundary line removed, or its k < 5 made k < 4, changed no test.
TEST_F(GeoFlagsCpuTest, MatchesReferenceAndShaderS5WhereZoneBoundariesFallOnPairs) {
  const Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  VisibilitySettings s;
  s.supersample = 5;
  expect_all_agree(context(), camera, 48, 36, s);
}

// One pixel at S = 4 whose samples (and ring) lie on triangle 1 where `inside` says so and
// on the background elsewhere: the flag byte names the way the edge runs and its zones.
uint8_t one_pixel_byte(bool (*inside)(int gx, int gy)) {
  const int S = 4, stride = S + 2;
  std::vector<uint32_t> ids(size_t(stride) * stride);
  for (int gy = -1; gy <= S; ++gy)
    for (int gx = -1; gx <= S; ++gx) ids[size_t(gy + 1) * stride + size_t(gx + 1)] = inside(gx, gy) ? 1u : 0u;
  gpu::FlagPush p{};
  p.frame = glm::ivec4(1, 1, S, 1);
  p.limits = glm::vec4(0.9f, 0.02f, 0.0f, 0.0f);
  return geo_flags_cpu(ids, {glm::vec4(0.0f, 0.0f, 1.0f, -1.0f)}, p).flags[0];
}

TEST(GeoFlagsCpu, TheByteNamesTheWayTheEdgeRunsAndTheZonesItMeets) {
  auto zones = [](uint8_t byte) { return byte >> kGeoZoneShift; };
  // A vertical edge between sample columns 1 and 2 (u = 0.5): horizontal frame, zone z2.
  const uint8_t middle = one_pixel_byte([](int gx, int) { return gx < 2; });
  EXPECT_EQ(middle & (kGeoEdge | kGeoAlongX), kGeoEdge);
  EXPECT_EQ(zones(middle), 0b00100);
  // Between columns 0 and 1 (u = 0.25): z1; at the ring on the right (u = 1): z4.
  EXPECT_EQ(zones(one_pixel_byte([](int gx, int) { return gx < 1; })), 0b00010);
  EXPECT_EQ(zones(one_pixel_byte([](int gx, int) { return gx < 4; })), 0b10000);
  // A horizontal edge between sample rows 0 and 1 (y = 0.25): along x, the vertical frame,
  // whose canonical u is 1 - y = 0.75: z3. One row lower (y = 0.5): z2.
  const uint8_t upper = one_pixel_byte([](int, int gy) { return gy < 1; });
  EXPECT_EQ(upper & (kGeoEdge | kGeoAlongX), kGeoEdge | kGeoAlongX);
  EXPECT_EQ(zones(upper), 0b01000);
  EXPECT_EQ(zones(one_pixel_byte([](int, int gy) { return gy < 2; })), 0b00100);
  // A diagonal edge meets several zones; nothing differs, nothing is flagged.
  EXPECT_GT(std::popcount(unsigned(zones(one_pixel_byte([](int gx, int gy) { return gx < gy; })))), 1);
  EXPECT_EQ(one_pixel_byte([](int, int) { return true; }), 0);
}

TEST(GeoMap, ZoneBitsOnABoundaryNameBothNeighbours) {
  // S = 4: midpoints u = i / 4 fall inside zones; S = 5: u = 0.2, 0.4, ... on boundaries.
  for (int i = 0; i <= 4; ++i) EXPECT_EQ(map_zone_at(10 * i, 4), 1 << std::min(i, 4)) << i;
  EXPECT_EQ(map_zone_at(0, 5), 0b00001);
  EXPECT_EQ(map_zone_at(10, 5), 0b00011);
  EXPECT_EQ(map_zone_at(40, 5), 0b11000);
  EXPECT_EQ(map_zone_at(50, 5), 0b10000);
  EXPECT_EQ(geo_flag_byte(0, 0, 0b11111, 0b11111), 0);
  EXPECT_EQ(geo_flag_byte(2, 1, 0b00110, 0b10000), kGeoEdge | 0b00110 << kGeoZoneShift);
  EXPECT_EQ(geo_flag_byte(1, 2, 0b00110, 0b10000), kGeoEdge | kGeoAlongX | 0b10000 << kGeoZoneShift);
}

// h = n.(v0 - origin) at the triangle's FIRST vertex, as triangle_planes.comp computes it
// from its first_vertices buffer: the oracle then divides the same floats as the shader
// where rounding leaves the other vertices a little off the plane. With a normal given that
// is not the triangle's own, each vertex gives another offset. Mutation testing: the
// second vertex for the first changed no test.
TEST(GeoFlagsCpu, TrianglePlanesTakeTheOffsetAtTheFirstVertex) {
  const std::vector<glm::vec3> positions = {{0.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -2.0f}, {0.0f, 1.0f, -3.0f}};
  const std::vector<glm::vec4> planes = triangle_planes(positions, {glm::vec4(0.0f, 0.0f, 1.0f, 7.0f)}, {0.0f, 0.0f, 0.5f});
  ASSERT_EQ(planes.size(), 1u);
  EXPECT_EQ(planes[0], glm::vec4(0.0f, 0.0f, 1.0f, -1.5f));  // the normal as given, w = -1 - 0.5
}

TEST(GeoFlagsCpu, TheMaterialRuleNeedsTheNormals) {
  gpu::FlagPush p{};
  p.frame = glm::ivec4(1, 1, 1, 1);
  p.limits = glm::vec4(0.9f, 0.02f, 1.0f, 0.0f);
  EXPECT_THROW(geo_flags_cpu(std::vector<uint32_t>(9, 0), {}, p), Error);
  // Normals, but not one per plane: refused too, not read past their end. Mutation testing:
  // neither this nor the id image's size check (below) was tested.
  const std::vector<glm::vec4> planes(2, glm::vec4(0.0f, 0.0f, 1.0f, -1.0f)), one(1, glm::vec4(0.0f, 0.0f, 1.0f, 0.0f));
  EXPECT_THROW(geo_flags_cpu(std::vector<uint32_t>(9, 1), planes, p, &one), Error);
  EXPECT_NO_THROW(geo_flags_cpu(std::vector<uint32_t>(9, 1), planes, p, &planes));
}

// The id image must be the frame's, ring included: (W S + 2) x (H S + 2).
TEST(GeoFlagsCpu, AnIdImageOfAnotherSizeIsRefused) {
  gpu::FlagPush p{};
  p.frame = glm::ivec4(2, 1, 2, 1);
  p.limits = glm::vec4(0.9f, 0.02f, 0.0f, 0.0f);
  const std::vector<glm::vec4> planes(1, glm::vec4(0.0f, 0.0f, 1.0f, -1.0f));
  EXPECT_NO_THROW(geo_flags_cpu(std::vector<uint32_t>(6 * 4, 1), planes, p));
  EXPECT_THROW(geo_flags_cpu(std::vector<uint32_t>(6 * 4 - 1, 1), planes, p), Error);
  EXPECT_THROW(geo_flags_cpu(std::vector<uint32_t>(6 * 5, 1), planes, p), Error);  // a row too many
}

}  // namespace
}  // namespace zz::test
