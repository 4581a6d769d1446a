// What the visibility map's thresholds mean, not only that three implementations agree
// (shaders/geo_flags.comp; FlagReference; host/gpu/geo_flags_cpu.cpp). The rule, as the
// shader documents it: a pair of samples on two triangles differs when their camera-facing
// geometric normals are more than VisibilitySettings::normal_angle_deg apart (cos below
// limits.x), or when the two planes, both intersected with the same sample ray, are more
// than depth_rel * min(t_a, t_b) apart along it. Scenes are built so the expected flags
// follow from geometry alone: a fold of known dihedral angle, parallel planes of a known
// relative depth gap, a coplanar grid with mixed winding. Checked on the GPU map, the SSE
// host rule and the scalar reference, all from the same rasterised ids.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "flag_reference.h"
#include "gpu/geo_flags_cpu.h"
#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_busy_scene.h"

namespace zz::test {
namespace {

using FlagSemanticsTest = GpuTest;

constexpr int kW = 32, kH = 24;

// The camera at the origin looking down -z: world x = 0 projects onto image column 16.0
// (the border between pixel columns 15 and 16, between sample columns 63 and 64 at S = 4).
Camera axis_camera() { return Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f); }

struct Maps {
  GeoMap gpu, sse, reference;
  std::vector<uint32_t> ids;
};

Maps all_maps(VulkanContext& context, const Scene& scene, const VisibilitySettings& s) {
  const Camera camera = axis_camera();
  VisibilityPass pass(context, scene);
  Maps m;
  m.gpu = pass.run(camera, kW, kH, s);
  m.ids = pass.render_ids(camera, kW, kH, s);
  const std::vector<glm::vec4> normals = geometric_normals(scene);
  const gpu::FlagPush push = make_flag_push(camera, kW, kH, s);
  m.reference = FlagReference{m.ids, scene.positions, normals, push}.map();
  m.sse = geo_flags_cpu(m.ids, triangle_planes(scene.positions, normals, glm::vec3(push.origin)), push, &normals);
  return m;
}

// Every map flags exactly the pixel columns in `columns` (all rows), nothing else.
void expect_flagged_columns(const Maps& m, std::vector<int> columns, const std::string& what) {
  for (const GeoMap* map : {&m.gpu, &m.sse, &m.reference}) {
    const char* name = map == &m.gpu ? "gpu" : map == &m.sse ? "sse" : "reference";
    ASSERT_EQ(map->width, kW);
    ASSERT_EQ(map->height, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const bool want = std::find(columns.begin(), columns.end(), x) != columns.end();
        EXPECT_EQ(map->at(x, y), want) << what << " " << name << " pixel " << x << "," << y;
      }
  }
}

// Every visible sample sees a triangle (no background anywhere, ring included).
void expect_no_background(const Maps& m) {
  for (uint32_t id : m.ids) ASSERT_NE(id, 0u) << "the scene must fill the frame";
}

// Two large quads meeting along the vertical line x = 0, z = -3, each receding from the
// crease by half the dihedral angle (a roof pointing at the camera): their normals are
// (-sin a, 0, cos a) and (sin a, 0, cos a), a = angle / 2, whose dot product is cos(angle).
// `flip_right` reverses the right quad's winding (its normal points away from the camera).
Scene fold(double angle_deg, bool flip_right) {
  const double a = angle_deg * M_PI / 360.0;
  const float L = 8.0f, Y = 8.0f;
  const glm::vec3 left_far(float(-L * std::cos(a)), 0.0f, float(-3.0 - L * std::sin(a)));
  const glm::vec3 right_far(float(L * std::cos(a)), 0.0f, float(-3.0 - L * std::sin(a)));
  const glm::vec3 up(0.0f, Y, 0.0f), c(0.0f, 0.0f, -3.0f);
  SceneBuilder b;
  b.quad(left_far - up, c - up, c + up, left_far + up);
  if (flip_right) b.quad(c - up, c + up, right_far + up, right_far - up);
  else b.quad(c - up, right_far - up, right_far + up, c + up);
  return b.done();
}

TEST_F(FlagSemanticsTest, AFoldFlagsOnlyBeyondTheNormalAngle) {
  for (float threshold : {25.0f, 10.0f}) {
    VisibilitySettings s;
    s.normal_angle_deg = threshold;
    for (bool flip : {false, true}) {
      const std::string what = "threshold " + std::to_string(threshold) + (flip ? " flipped" : "");
      // The geometry is what the test says: the normals' dot product is cos(angle).
      const Scene below = fold(threshold - 1.0, flip), above = fold(threshold + 1.0, flip);
      const std::vector<glm::vec4> n = geometric_normals(above);
      const double c = std::fabs(glm::dot(glm::dvec3(glm::vec3(n[0])), glm::dvec3(glm::vec3(n[2]))));
      EXPECT_NEAR(c, std::cos((threshold + 1.0) * M_PI / 180.0), 1e-6);
      const Maps lo = all_maps(context(), below, s), hi = all_maps(context(), above, s);
      expect_no_background(lo);
      expect_no_background(hi);
      // 1° inside the threshold: the crease is smooth enough, and the planes meet along it
      // (the depth test, along the same ray, sees a gap of ~0.1 % near the crease).
      expect_flagged_columns(lo, {}, what + " below");
      // 1° beyond: exactly the two pixel columns whose samples (ring included) straddle it.
      expect_flagged_columns(hi, {15, 16}, what + " above");
    }
  }
}

// A near plane z = -3 over x < 0 in front of a far plane over the whole view at
// z = -3 (1 + gap): along any ray t is proportional to -z for both planes, so the relative
// gap |t_a - t_b| / min(t_a, t_b) is exactly `gap`.
Scene parallel_planes(double gap) {
  const float z0 = -3.0f, z1 = float(-3.0 * (1.0 + gap)), X = 20.0f;
  SceneBuilder b;
  b.quad({-X, -X, z0}, {0.0f, -X, z0}, {0.0f, X, z0}, {-X, X, z0});
  b.quad({-X, -X, z1}, {X, -X, z1}, {X, X, z1}, {-X, X, z1});
  return b.done();
}

TEST_F(FlagSemanticsTest, ParallelPlanesFlagOnlyBeyondTheRelativeDepth) {
  for (float rel : {0.02f, 0.005f}) {
    VisibilitySettings s;
    s.depth_rel = rel;
    const std::string what = "depth_rel " + std::to_string(rel);
    const Maps near_gap = all_maps(context(), parallel_planes(0.9 * rel), s);
    const Maps far_gap = all_maps(context(), parallel_planes(1.1 * rel), s);
    expect_no_background(near_gap);
    expect_no_background(far_gap);
    expect_flagged_columns(near_gap, {}, what + " x0.9");
    expect_flagged_columns(far_gap, {15, 16}, what + " x1.1");
    // The limit is rel times the nearer depth, not the farther: a gap of rel (1 +- rel / 2)
    // lies on either side of it, where rel times the farther depth (rel + rel^2) would not
    // flag either (mutation testing: max for min changed no test).
    expect_flagged_columns(all_maps(context(), parallel_planes(rel * (1.0 - rel / 2)), s), {}, what + " x(1 - rel/2)");
    expect_flagged_columns(all_maps(context(), parallel_planes(rel * (1.0 + rel / 2)), s), {15, 16}, what + " x(1 + rel/2)");
  }
}

// A plane seen at 60° from its normal (grazing towards the top of the frame) tessellated
// into a grid of cells split along a diagonal, the lower-right triangle of every cell wound
// one way and the upper-left one the other: every shared edge (diagonals and cell borders)
// joins two oppositely wound triangles. Camera-facing normals agree and the planes meet
// along the shared edges, so nothing is flagged, at S = 4 and 6 and tight thresholds.
// Control: with every other row of cells moved `step_back` along the normal (a parallel
// plane), the row borders do flag: the scene does exercise the rule.
Scene mixed_winding_grid(double step_back) {
  const double beta = 60.0 * M_PI / 180.0;
  const glm::dvec3 p0(0.0, 0.0, -3.0), u(1.0, 0.0, 0.0), v(0.0, std::cos(beta), -std::sin(beta));
  const glm::dvec3 n(0.0, std::sin(beta), std::cos(beta));
  const int cells = 16;
  const double half = 20.0, step = 2 * half / cells;
  SceneBuilder b;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const double back = j % 2 ? step_back : 0.0;
      auto at = [&](int ii, int jj) { return glm::vec3(p0 + (ii * step - half) * u + (jj * step - half) * v - back * n); };
      const glm::vec3 a = at(i, j), r = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      b.tri(a, r, c);  // normal +u x v
      b.tri(a, d, c);  // normal -u x v
    }
  return b.done();
}

TEST_F(FlagSemanticsTest, ACoplanarGridWithMixedWindingFlagsNothing) {
  const Scene grid = mixed_winding_grid(0.0);
  {  // the winding really is mixed: half the normals point each way
    const std::vector<glm::vec4> n = geometric_normals(grid);
    int towards = 0;
    for (const glm::vec4& g : n) towards += g.z > 0.0f;
    EXPECT_EQ(towards, int(n.size()) / 2);
  }
  for (int ss : {4, 6}) {
    VisibilitySettings s;
    s.supersample = ss;
    s.normal_angle_deg = 2.0f;
    s.depth_rel = 0.002f;
    const Maps m = all_maps(context(), grid, s);
    expect_no_background(m);
    // Many triangles are in view (the rule is exercised across many shared edges).
    std::vector<bool> seen(grid.positions.size() / 3 + 1, false);
    for (uint32_t id : m.ids) seen[id] = true;
    EXPECT_GT(std::count(seen.begin(), seen.end(), true), 20);
    expect_flagged_columns(m, {}, "grid S=" + std::to_string(ss));
  }
  // Control: the same grid with every other row of cells 0.15 further back (along the
  // normal; ~5 % of the distance near the frame's bottom) flags.
  VisibilitySettings s;
  s.depth_rel = 0.02f;
  const Maps broken = all_maps(context(), mixed_winding_grid(0.15), s);
  EXPECT_GT(flagged(broken.gpu), size_t(kW));
  EXPECT_EQ(broken.gpu.flags, broken.sse.flags);
  EXPECT_EQ(broken.gpu.flags, broken.reference.flags);
}

// Both thresholds are strict ("more than ... apart"): a pair exactly at one does not flag.
// Along the axis camera's rays (z component exactly -1) planes z = -3 and z = -4.5 are hit
// at t = 3 and 4.5 exactly, so their gap 1.5 equals 0.5 * min(t) to the last bit; and with
// a threshold of 0 degrees (limits.x = cos 0 = 1) the quads' own diagonals join triangles
// whose normals are exactly (0, 0, 1), a dot product of exactly 1. Mutation testing: `<=`
// for `<` in the shader's and the SSE rule's depth or angle test changed no test.
TEST_F(FlagSemanticsTest, APairExactlyAtAThresholdDoesNotFlag) {
  const Scene planes = parallel_planes(0.5);
  ASSERT_EQ(planes.positions[6].z, -4.5f);
  VisibilitySettings s;
  s.depth_rel = 0.5f;
  s.normal_angle_deg = 0.0f;
  ASSERT_EQ(make_flag_push(axis_camera(), kW, kH, s).limits.x, 1.0f);
  const Maps at = all_maps(context(), planes, s);
  expect_no_background(at);
  expect_flagged_columns(at, {}, "gap exactly depth_rel, normals exactly equal");
  // One float below the depth limit the step flags, as its two columns only.
  s.depth_rel = std::nextafter(0.5f, 0.0f);
  expect_flagged_columns(all_maps(context(), planes, s), {15, 16}, "depth_rel one float below the gap");
}

// make_flag_push places supersample (gx, gy), ring included, where the raster does: the
// ray of CameraRays at image point ((gx + 0.5) / S, (gy + 0.5) / S) (visibility_shared.h),
// a pinhole's by its direction, an orthographic camera's by its origin; and an orthographic
// view's depth scale du.w is the view's height (2 ymag), whatever the frame's aspect.
// Mutation testing: half a sample dropped from dir00 or from the orthographic origin along
// v, or the view's width for its height, changed no test: the flag pass then intersects
// the planes with rays off the samples the ids come from.
TEST(FlagPush, SupersamplesSitAtTheirCentresAndTheOrthographicScaleIsTheViewsHeight) {
  const int w = 40, h = 24;
  Camera camera = Camera::look_at({0.4f, 0.9f, 2.8f}, {0.0f, 0.1f, -0.2f}, {0, 1, 0}, 0.8f);
  for (const float ymag : {0.0f, 1.3f}) {
    camera.ymag = ymag;
    const CameraRays rays(camera, w, h);
    for (int S : {4, 6}) {
      VisibilitySettings s;
      s.supersample = S;
      const gpu::FlagPush p = make_flag_push(camera, w, h, s);
      ASSERT_EQ(p.limits.w, ymag > 0.0f ? 1.0f : 0.0f);
      if (ymag > 0.0f) {
        EXPECT_FLOAT_EQ(p.du.w, 2.0f * ymag);
      }
      for (int gx : {-1, 0, 7, w * S})
        for (int gy : {-1, 0, 5, h * S}) {
          const float px = (gx + 0.5f) / float(S), py = (gy + 0.5f) / float(S);
          const glm::vec3 step = float(gx) * glm::vec3(p.du) + float(gy) * glm::vec3(p.dv);
          if (ymag > 0.0f) {
            EXPECT_LT(glm::length(glm::vec3(p.origin) + step - rays.origin_at(px, py)), 1e-4f) << gx << "," << gy;
            EXPECT_LT(glm::length(glm::normalize(glm::vec3(p.dir00)) - rays.direction(px, py)), 1e-5f);
          } else {
            EXPECT_EQ(glm::vec3(p.origin), rays.origin);
            EXPECT_LT(glm::length(glm::normalize(glm::vec3(p.dir00) + step) - rays.direction(px, py)), 1e-5f)
                << gx << "," << gy << " S " << S;
          }
        }
    }
  }
}

}  // namespace
}  // namespace zz::test
