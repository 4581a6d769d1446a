// Bad inputs: no crash, no error, sensible flags.
#include <gtest/gtest.h>

#include "core/error.h"
#include "flag_reference.h"
#include "gpu/geo_flags_cpu.h"
#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_scenes.h"

namespace zz::test {
namespace {

using RobustnessTest = GpuTest;

size_t count(const GeoMap& m) {
  size_t n = 0;
  for (uint8_t f : m.flags) n += f != 0;
  return n;
}

TEST_F(RobustnessTest, EmptySceneFlagsNothing) {
  Scene scene = SceneBuilder().done();
  VisibilityPass pass(context(), scene);
  GeoMap map = pass.run(scene.cameras[0], 33, 17);
  EXPECT_EQ(map.width, 33);
  EXPECT_EQ(map.height, 17);
  EXPECT_EQ(count(map), 0u);
  for (uint32_t id : pass.render_ids(scene.cameras[0], 33, 17)) ASSERT_EQ(id, 0u);
}

TEST_F(RobustnessTest, CameraInsideABoxSeesOnlyItsCreases) {
  SceneBuilder b;
  b.box({-1.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f});
  Scene scene = b.done();
  Camera camera = Camera::look_at({0.1f, 0.05f, 0.0f}, {0.1f, 0.05f, -1.0f}, {0, 1, 0}, 2.0f);
  const int w = 64, h = 64;
  VisibilityPass pass(context(), scene);
  for (uint32_t id : pass.render_ids(camera, w, h)) ASSERT_NE(id, 0u) << "a closed box has no background";
  GeoMap map = pass.run(camera, w, h);
  size_t n = count(map);
  EXPECT_GT(n, size_t(2 * w)) << "the four creases around the back face";
  EXPECT_LT(n, size_t(w * h / 8));
  // The back face's centre region and the side walls' middles are smooth.
  for (int y = 26; y < 38; ++y)
    for (int x = 26; x < 38; ++x) EXPECT_FALSE(map.at(x, y)) << x << "," << y;
}

TEST_F(RobustnessTest, TrianglesBehindOrThroughTheCamera) {
  SceneBuilder b;
  b.tri({-1.0f, -1.0f, 1.0f}, {1.0f, -1.0f, 1.0f}, {0.0f, 1.0f, 1.0f});  // behind (camera looks -z)
  Scene behind = b.done();
  Camera camera = Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f);
  {
    VisibilityPass pass(context(), behind);
    EXPECT_EQ(count(pass.run(camera, 40, 30)), 0u);
    for (uint32_t id : pass.render_ids(camera, 40, 30)) ASSERT_EQ(id, 0u);
  }
  // A triangle crossing the camera plane: its visible part spans the frame's lower half.
  b.tri({-5.0f, -0.5f, 5.0f}, {5.0f, -0.5f, 5.0f}, {0.0f, -0.5f, -5.0f});
  Scene through = b.done();
  VisibilityPass pass(context(), through);
  std::vector<uint32_t> ids = pass.render_ids(camera, 40, 30);
  size_t seen = 0;
  for (uint32_t id : ids) seen += id == 2;
  EXPECT_GT(seen, ids.size() / 4);
  GeoMap map = pass.run(camera, 40, 30);
  EXPECT_GT(count(map), 0u);
  for (int x = 0; x < 40; ++x) EXPECT_FALSE(map.at(x, 29)) << "inside the floor triangle, x=" << x;
}

TEST_F(RobustnessTest, ExtremeDistancesFrom1em4To1e6) {
  SceneBuilder b;
  // A 1e-4-sized triangle 1e-4 in front of the camera, and a wall 1e6 away, 1e7 wide.
  b.tri({-0.5e-4f, -0.5e-4f, -1e-4f}, {0.5e-4f, -0.5e-4f, -1e-4f}, {0.0f, 0.5e-4f, -1e-4f});
  b.quad({-1e7f, -1e7f, -1e6f}, {1e7f, -1e7f, -1e6f}, {1e7f, 1e7f, -1e6f}, {-1e7f, 1e7f, -1e6f});
  Scene scene = b.done();
  Camera camera = Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f);
  const int w = 64, h = 48;
  VisibilityPass pass(context(), scene);
  std::vector<uint32_t> ids = pass.render_ids(camera, w, h);
  int sw = w * 4 + 2;
  EXPECT_EQ(ids[size_t(h * 2 + 1) * sw + w * 2 + 1], 1u) << "the near triangle covers the centre";
  uint32_t corner = ids[size_t(5) * sw + 5];
  EXPECT_TRUE(corner == 2u || corner == 3u) << "the far wall covers the corner";
  GeoMap map = pass.run(camera, w, h);
  size_t n = count(map);
  EXPECT_GT(n, 20u) << "the near triangle's outline";
  EXPECT_LT(n, size_t(w * h / 4));
  EXPECT_FALSE(map.at(2, 2));
  EXPECT_FALSE(map.at(w - 3, h - 3));
}

TEST_F(RobustnessTest, DegenerateTrianglesAndTinyFrames) {
  SceneBuilder b;
  b.tri({0.0f, 0.0f, -1.0f}, {0.0f, 0.0f, -1.0f}, {0.0f, 0.0f, -1.0f});  // a point
  b.tri({-1.0f, 0.0f, -2.0f}, {0.0f, 0.0f, -2.0f}, {1.0f, 0.0f, -2.0f});  // a line
  b.tri({-1.0f, -1.0f, -3.0f}, {1.0f, -1.0f, -3.0f}, {0.0f, 1.0f, -3.0f});
  Scene scene = b.done();
  Camera camera = Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  const std::vector<glm::vec4> normals = geometric_normals(scene);
  // Degenerate triangles have a zero normal (geometric_normals), the real one does not.
  EXPECT_EQ(glm::vec3(normals[0]), glm::vec3(0.0f));
  EXPECT_EQ(glm::vec3(normals[1]), glm::vec3(0.0f));
  EXPECT_NEAR(glm::length(glm::vec3(normals[2])), 1.0f, 1e-6f);
  for (int size : {1, 2, 3, 5, 33}) {
    GeoMap map = pass.run(camera, size, size);
    EXPECT_EQ(map.width, size);
    EXPECT_EQ(map.height, size);
    ASSERT_EQ(map.flags.size(), size_t(size * size));
    // A point and a line cover no sample: their ids (1, 2) never show; the real
    // triangle (id 3) covers the frame's centre.
    const std::vector<uint32_t> ids = pass.render_ids(camera, size, size);
    const int sw = size * 4 + 2;
    ASSERT_EQ(ids.size(), size_t(sw) * sw);
    for (uint32_t id : ids) ASSERT_TRUE(id == 0u || id == 3u) << "id " << id << " at size " << size;
    EXPECT_EQ(ids[size_t(sw / 2) * sw + sw / 2], 3u) << size;
    // The GPU map is the rule's, bit for bit, at every size (scalar reference and SSE).
    const gpu::FlagPush push = make_flag_push(camera, size, size, {});
    EXPECT_EQ(map.flags, (FlagReference{ids, scene.positions, normals, push}.map().flags)) << size;
    EXPECT_EQ(map.flags, geo_flags_cpu(ids, triangle_planes(scene.positions, normals, glm::vec3(push.origin)), push)
                             .flags)
        << size;
    if (size == 33) {  // the triangle's outline (and only it) flags: a meaningful comparison
      EXPECT_GT(count(map), 33u);
      EXPECT_LT(count(map), size_t(33 * 33 / 3));
      EXPECT_FALSE(map.at(16, 20)) << "inside the triangle";
    }
  }
  VisibilitySettings bad;
  bad.supersample = 0;
  EXPECT_THROW(pass.run(camera, 8, 8, bad), Error);
  EXPECT_THROW(pass.run(camera, 0, 8), Error);
}

// Supersampling runs up to ZZ_MAX_SUPERSAMPLE (16) per axis and is refused beyond. Mutation
// testing: refusing 16 too changed no test.
TEST_F(RobustnessTest, SupersamplingUpTo16IsMadeAndBeyondRefused) {
  SceneBuilder b;
  b.tri({-1.0f, -1.0f, -3.0f}, {1.0f, -1.0f, -3.0f}, {0.0f, 1.0f, -3.0f});
  const Scene scene = b.done();
  const Camera camera = Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f);
  VisibilityPass pass(context(), scene);
  VisibilitySettings s;
  s.supersample = ZZ_MAX_SUPERSAMPLE;
  ASSERT_EQ(s.supersample, 16);
  const GeoMap map = pass.run(camera, 9, 7, s);
  const std::vector<uint32_t> ids = pass.render_ids(camera, 9, 7, s);
  const gpu::FlagPush push = make_flag_push(camera, 9, 7, s);
  EXPECT_EQ(map.flags, (FlagReference{ids, scene.positions, geometric_normals(scene), push}.map().flags));
  EXPECT_GT(count(map), 0u);
  s.supersample = ZZ_MAX_SUPERSAMPLE + 1;
  EXPECT_THROW(pass.run(camera, 9, 7, s), Error);
}

}  // namespace
}  // namespace zz::test
