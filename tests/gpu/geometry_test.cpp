// Geometry truths of the flag map with the default thresholds: smooth surfaces flag only
// their silhouettes, creases flag, coplanar tessellation never flags, thin features flag.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_scenes.h"

namespace zz::test {
namespace {

using GeometryTest = GpuTest;

// Image-plane position (pixels) of a world point, inverting CameraRays exactly.
glm::dvec2 project(const CameraRays& rays, glm::dvec3 p) {
  if (rays.orthographic) {  // p - origin = px ou + py ov + t dir00
    glm::dmat3 m(glm::dvec3(rays.ou), glm::dvec3(rays.ov), glm::dvec3(rays.dir00));
    glm::dvec3 a = glm::inverse(m) * (p - glm::dvec3(rays.origin));
    return {a.x, a.y};
  }
  glm::dmat3 m(glm::dvec3(rays.du), glm::dvec3(rays.dv), glm::dvec3(rays.dir00));
  glm::dvec3 a = glm::inverse(m) * (p - glm::dvec3(rays.origin));
  return {a.x / a.z, a.y / a.z};
}

double segment_distance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  glm::dvec2 ab = b - a;
  double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

size_t count(const GeoMap& m) {
  size_t n = 0;
  for (uint8_t f : m.flags) n += f != 0;
  return n;
}

// Also through an orthographic camera (ymag > 0), whose silhouette is where the parallel
// rays pass the centre at one radius: the depth rule, which intersects both facets' planes
// with one ray from its own origin, must keep the smooth facets apart from it.
TEST_F(GeometryTest, SmoothSphereFlagsOnlyItsSilhouette) {
  for (const float ymag : {0.0f, 1.3f})
    for (int slices : {48, 128}) {
      SceneBuilder b;
      glm::dvec3 center(0.1, -0.05, 0.0);
      double radius = 1.0;
      b.sphere(glm::vec3(center), float(radius), slices, slices / 2);
      Scene scene = b.done();
      Camera camera = Camera::look_at({0.3f, 0.5f, 3.4f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f);
      camera.ymag = ymag;
      const int w = 96, h = 80;
      for (int ss : {4, 6}) {
        VisibilityPass pass(context(), scene);
        VisibilitySettings s;
        s.supersample = ss;
        GeoMap map = pass.run(camera, w, h, s);
        CameraRays rays(camera, w, h);
        // In pixels: a pinhole's silhouette is a cone of half-angle beta around the centre
        // (pixels are slightly smaller in angle off-centre; 1.25 keeps the bound safe), an
        // orthographic one a cylinder of the sphere's radius.
        const auto from_silhouette = [&](int x, int y) {
          glm::dvec3 o(rays.origin_at(x + 0.5f, y + 0.5f)), d(rays.direction(x + 0.5f, y + 0.5f));
          if (rays.orthographic) {
            const glm::dvec3 to_centre = center - o;
            return std::abs(glm::length(to_centre - glm::dot(to_centre, d) * d) - radius) / glm::length(glm::dvec3(rays.ou));
          }
          double beta = std::asin(radius / glm::length(center - o));
          double alpha = std::acos(std::clamp(glm::dot(d, glm::normalize(center - o)), -1.0, 1.0));
          return std::abs(alpha - beta) / glm::length(glm::dvec3(rays.du)) * 1.25;  // dir00 ~ unit
        };
        size_t inner = 0, missed = 0, on_silhouette = 0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const double px = from_silhouette(x, y);
            bool flag = map.at(x, y);
            if (flag && px > 1.6) ++inner;
            if (px < 0.3) {
              ++on_silhouette;
              if (!flag) ++missed;
            }
          }
        EXPECT_EQ(inner, 0u) << "flags away from the silhouette, slices=" << slices << " S=" << ss << " ymag " << ymag;
        EXPECT_EQ(missed, 0u) << "of " << on_silhouette << " silhouette pixels unflagged, ymag " << ymag;
        EXPECT_GT(on_silhouette, 50u);
      }
    }
}

// An orthographic view is the same from anywhere along its axis, and so is its map: the
// depth rule's scale is the view's height, not the distance from the camera's plane
// (review: from 100 times as far, a rod's outline against its wall was no longer flagged;
// with the plane close, smooth facets were).
TEST_F(GeometryTest, AnOrthographicMapDoesNotDependOnWhereTheCameraSitsOnItsAxis) {
  SceneBuilder b;
  b.quad({-1.5f, -0.5f, -1.0f}, {1.5f, -0.5f, -1.0f}, {1.5f, 1.2f, -1.0f}, {-1.5f, 1.2f, -1.0f});  // wall
  b.box({-0.6f, 0.0f, -0.96f}, {0.6f, 0.03f, -0.9f});  // a rod 0.1 before it: a depth step alone
  b.sphere({0.3f, 0.6f, -0.5f}, 0.3f, 48, 24);
  const Scene scene = b.done();
  VisibilityPass pass(context(), scene);
  std::vector<uint8_t> first;
  for (const float eye_z : {0.0f, 3.0f, 300.0f}) {
    Camera camera = Camera::look_at({0.05f, 0.35f, eye_z}, {0.05f, 0.35f, eye_z - 1.0f}, {0, 1, 0}, 0.8f);
    camera.ymag = 0.6f;  // a view 1.2 tall: the depth rule flags steps above 0.024
    const GeoMap map = pass.run(camera, 96, 64);
    const CameraRays rays(camera, 96, 64);
    const glm::dvec2 rod = project(rays, {0.0, 0.015, -0.9});  // the rod's front, mid-length
    EXPECT_TRUE(map.at(int(rod.x), int(rod.y) - 1) || map.at(int(rod.x), int(rod.y)) || map.at(int(rod.x), int(rod.y) + 1))
        << "the rod's outline, eye at z " << eye_z;
    if (first.empty()) first = map.flags;
    EXPECT_EQ(map.flags, first) << "eye at z " << eye_z;
  }
}

void cube_flags_silhouette_and_creases(VulkanContext& context, float ymag) {
  SceneBuilder b;
  b.box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
  Scene scene = b.done();
  glm::dvec3 eye(1.6, 1.3, 2.1);
  Camera camera = Camera::look_at(glm::vec3(eye), {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f);
  camera.ymag = ymag;
  const int w = 90, h = 70;
  VisibilityPass pass(context, scene);
  GeoMap map = pass.run(camera, w, h);
  CameraRays rays(camera, w, h);
  // Edges of the convex box are visible when one of their two faces faces the eye.
  std::vector<std::pair<glm::dvec2, glm::dvec2>> visible;
  int creases = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int s1 : {-1, 1})
      for (int s2 : {-1, 1}) {
        int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
        glm::dvec3 p(0.0), q(0.0);
        p[a1] = q[a1] = 0.5 * s1;
        p[a2] = q[a2] = 0.5 * s2;
        p[axis] = -0.5;
        q[axis] = 0.5;
        bool f1 = s1 * (eye[a1] - 0.5 * s1) > 0, f2 = s2 * (eye[a2] - 0.5 * s2) > 0;
        if (!f1 && !f2) continue;
        creases += f1 && f2;
        visible.push_back({project(rays, p), project(rays, q)});
      }
  ASSERT_EQ(visible.size(), 9u);  // 6 silhouette edges + 3 creases from the near corner
  ASSERT_EQ(creases, 3);
  size_t stray = 0, missed = 0, on_edge = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::dvec2 c(x + 0.5, y + 0.5);
      double dist = 1e9;
      for (auto& e : visible) dist = std::min(dist, segment_distance(c, e.first, e.second));
      if (map.at(x, y) && dist > 1.5) ++stray;
      if (dist < 0.3) {
        ++on_edge;
        if (!map.at(x, y)) ++missed;
      }
    }
  EXPECT_EQ(stray, 0u);
  EXPECT_EQ(missed, 0u) << "of " << on_edge;
  EXPECT_GT(on_edge, 100u);
}

// Also through an orthographic camera (ymag > 0), whose view of a box has parallel edges.
TEST_F(GeometryTest, CubeFlagsSilhouetteAndCreases) {
  for (const float ymag : {0.0f, 1.0f}) {
    SCOPED_TRACE(ymag);
    cube_flags_silhouette_and_creases(context(), ymag);
  }
}

TEST_F(GeometryTest, CoplanarTrianglesFlagNothing) {
  SceneBuilder b;
  // A tilted plane (not axis-aligned) tessellated into 2 x 24^2 triangles filling the frame.
  glm::vec3 u(4.0f, 0.6f, 0.0f), v(0.0f, 0.9f, -4.0f);
  b.grid({-2.0f, -0.8f, 2.0f}, u, v, 24);
  Scene scene = b.done();
  const Camera pinhole = Camera::look_at({0.2f, 1.0f, 0.9f}, {0.0f, -0.1f, -0.2f}, {0, 1, 0}, 0.7f);
  Camera orthographic = pinhole;
  orthographic.ymag = 0.6f;
  VisibilityPass pass(context(), scene);
  for (const Camera& camera : {pinhole, orthographic})
    for (int ss : {4, 6}) {
      VisibilitySettings s;
      s.supersample = ss;
      std::vector<uint32_t> ids = pass.render_ids(camera, 64, 48, s);
      size_t background = 0;
      for (uint32_t id : ids) background += id == 0;
      ASSERT_EQ(background, 0u) << "the plane must fill the frame";
      EXPECT_EQ(count(pass.run(camera, 64, 48, s)), 0u) << "S=" << ss << " ymag " << camera.ymag;
    }
}

TEST_F(GeometryTest, GrazingFloorFlagsOnlyAtTheHorizon) {
  // A 200 x 200 floor seen from height 1: distances along the floor vary by 100x and the
  // view grazes it, yet coplanar triangles must compare equal.
  SceneBuilder b;
  b.grid({-100.0f, 0.0f, 100.0f}, {200.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -200.0f}, 60);
  Scene scene = b.done();
  Camera camera = Camera::look_at({0.3f, 1.0f, 0.0f}, {0.3f, 1.0f, -1.0f}, {0, 1, 0}, 0.8f);
  const int w = 80, h = 64;
  VisibilityPass pass(context(), scene);
  GeoMap map = pass.run(camera, w, h);
  size_t below = 0, horizon = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!map.at(x, y)) continue;
      if (y >= h / 2 + 3) ++below;
      else ++horizon;
    }
  EXPECT_EQ(below, 0u) << "flags on the floor below the horizon";
  EXPECT_GE(horizon, size_t(w)) << "the floor's far edge against the sky is an edge";
}

TEST_F(GeometryTest, ThinFeaturesNarrowerThanAPixelAreFlagged) {
  SceneBuilder b;
  // A wall, and in front of it two slivers 0.4 px wide: one against the sky (above the
  // wall), one parallel to the wall (same normal: only the distance rule can see it).
  b.quad({-3.0f, -2.0f, -2.0f}, {3.0f, -2.0f, -2.0f}, {3.0f, 0.0f, -2.0f}, {-3.0f, 0.0f, -2.0f});
  const int w = 96, h = 64;
  Camera camera = Camera::look_at({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f);
  CameraRays rays(camera, w, h);
  float width = 0.4f * glm::length(rays.du) * 3.0f;  // 0.4 px at distance 3
  float x0 = 0.31f;
  b.quad({x0, -0.9f, 0.0f}, {x0 + width, -0.9f, 0.0f}, {x0 + width, 0.9f, 0.0f}, {x0, 0.9f, 0.0f});
  Scene scene = b.done();
  VisibilityPass pass(context(), scene);
  GeoMap map = pass.run(camera, w, h);
  glm::dvec2 top = project(rays, {x0, 0.85, 0.0}), bottom = project(rays, {x0, -0.85, 0.0});
  int rows = 0, rows_flagged = 0;
  for (int y = int(top.y) + 1; y < int(bottom.y); ++y) {
    ++rows;
    bool any = false;
    for (int x = 0; x < w; ++x)
      if (map.at(x, y) && std::abs(x + 0.5 - top.x) < 2.0) any = true;
    rows_flagged += any;
  }
  EXPECT_GT(rows, 30);
  EXPECT_EQ(rows_flagged, rows) << "every row the sliver crosses, over sky and over the wall";
}

// The flag byte says which way the edge runs (ZZ_GEO_ALONG_X): a square turned 4 degrees
// from the axes seen head-on; pixels on its top and bottom sides (the middle third of the
// columns) have edges along x, those on its left and right sides (the middle third of the
// rows) do not.
TEST_F(GeometryTest, TheFlagSaysWhichWayTheEdgeRuns) {
  SceneBuilder b;
  const float c = std::cos(0.07f), s = std::sin(0.07f);
  auto turned = [&](float x, float y) { return glm::vec3(c * x - s * y, s * x + c * y, 0.0f); };
  b.quad(turned(-0.8f, -0.8f), turned(0.8f, -0.8f), turned(0.8f, 0.8f), turned(-0.8f, 0.8f));
  const Scene scene = b.done();
  const Camera camera = Camera::look_at({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.8f);
  const int w = 72, h = 72;
  for (int ss : {4, 6}) {
    VisibilityPass pass(context(), scene);
    VisibilitySettings settings;
    settings.supersample = ss;
    const GeoMap map = pass.run(camera, w, h, settings);
    int along = 0, across = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!map.at(x, y)) continue;
        const bool middle_column = x >= w / 3 && x < 2 * w / 3, middle_row = y >= h / 3 && y < 2 * h / 3;
        ASSERT_FALSE(middle_column && middle_row) << "a flag inside the square at " << x << "," << y;
        if (middle_column) {
          EXPECT_TRUE(map.along_x(x, y)) << "top or bottom side at " << x << "," << y << ", S = " << ss;
          ++along;
        }
        if (middle_row) {
          EXPECT_FALSE(map.along_x(x, y)) << "left or right side at " << x << "," << y << ", S = " << ss;
          ++across;
        }
      }
    EXPECT_GE(along, 2 * (w / 3));  // both sides, every column, at least one pixel each
    EXPECT_GE(across, 2 * (h / 3));
  }
}

}  // namespace
}  // namespace zz::test
