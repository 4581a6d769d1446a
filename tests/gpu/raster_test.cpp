// The raster pass sees what the ray tracer sees: per supersample, the raster's triangle
// id equals the first hit of the ray through the same image-plane point.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "gpu/visibility.h"
#include "gpu_fixture.h"
#include "test_scenes.h"

namespace zz::test {
namespace {

using RasterTest = GpuTest;

Scene mixed_scene() {
  SceneBuilder b;
  b.sphere({-0.6f, 0.1f, 0.0f}, 0.5f, 48, 24);
  b.box({0.2f, -0.4f, -0.3f}, {0.8f, 0.3f, 0.3f});
  b.grid({-2.0f, -0.5f, 2.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -4.0f}, 8);  // floor
  b.tri({-0.2f, 0.6f, -0.8f}, {0.3f, 0.9f, -0.9f}, {0.0f, 0.2f, -1.0f});
  return b.done();
}

// Fraction of agreeing samples; every disagreement must sit next to a ray-traced edge.
// `traced`: the triangles the rays see, the rastered scene's first ones (by default all).
void check_agreement(VulkanContext& context, const Scene& scene, const Camera& camera, int w, int h, int s,
                     const Scene* traced_scene = nullptr) {
  const Scene& seen = traced_scene ? *traced_scene : scene;
  VisibilityPass pass(context, scene);
  VisibilitySettings settings;
  settings.supersample = s;
  std::vector<uint32_t> ids = pass.render_ids(camera, w, h, settings);
  int sw = w * s + 2, sh = h * s + 2;
  ASSERT_EQ(ids.size(), size_t(sw) * sh);
  CameraRays rays(camera, w, h);
  std::vector<uint32_t> traced(ids.size());
  for (int v = 0; v < sh; ++v)
    for (int u = 0; u < sw; ++u) {
      const float px = (u - 1 + 0.5f) / s, py = (v - 1 + 0.5f) / s;
      traced[size_t(v) * sw + u] =
          first_hit(seen, glm::dvec3(rays.origin_at(px, py)), glm::dvec3(rays.direction(px, py)));
    }
  size_t mismatches = 0, hits = 0;
  for (int v = 0; v < sh; ++v)
    for (int u = 0; u < sw; ++u) {
      size_t k = size_t(v) * sw + u;
      hits += traced[k] != 0;
      if (ids[k] == traced[k]) continue;
      ++mismatches;
      bool near_edge = false;
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          int uu = std::clamp(u + du, 0, sw - 1), vv = std::clamp(v + dv, 0, sh - 1);
          near_edge |= traced[size_t(vv) * sw + uu] != traced[k];
        }
      EXPECT_TRUE(near_edge) << "mismatch away from edges at sample " << u - 1 << "," << v - 1
                             << ": raster " << ids[k] << " ray " << traced[k];
    }
  std::printf("samples %zu, ray hits %zu, raster/ray mismatches %zu\n", ids.size(), hits, mismatches);
  EXPECT_GT(hits, ids.size() / 4) << "the scene should cover the frame substantially";
  EXPECT_LE(double(mismatches), 0.001 * double(ids.size())) << mismatches << " of " << ids.size();
}

TEST_F(RasterTest, IdsMatchPrimaryRaysS4) {
  Camera camera = Camera::look_at({0.3f, 0.8f, 2.6f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.9f);
  check_agreement(context(), mixed_scene(), camera, 80, 60, 4);
}

TEST_F(RasterTest, IdsMatchPrimaryRaysS6OddSize) {
  Camera camera = Camera::look_at({-1.5f, 0.4f, 2.0f}, {0.1f, 0.0f, -0.2f}, {0, 1, 0}, 0.7f);
  check_agreement(context(), mixed_scene(), camera, 37, 29, 6);
}

// An orthographic camera's parallel rays, from the plane through its position: the raster
// projects the same way, and draws nothing behind that plane (the second camera stands
// inside the scene, between the sphere and the box).
TEST_F(RasterTest, IdsMatchOrthographicRays) {
  Camera camera = Camera::look_at({0.3f, 0.8f, 2.6f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.9f);
  camera.ymag = 1.1f;
  check_agreement(context(), mixed_scene(), camera, 80, 60, 4);
  Camera inside = Camera::look_at({-0.2f, 0.1f, 0.0f}, {0.8f, 0.0f, -0.1f}, {0, 1, 0}, 0.9f);
  inside.ymag = 0.7f;
  check_agreement(context(), mixed_scene(), inside, 37, 29, 6);
}

// mixed_scene() behind a pane of material `pane_material` that covers most of the frame.
Scene behind_a_pane(const Material& pane_material) {
  Scene scene = mixed_scene();
  SceneBuilder pane;
  pane.quad({-3.0f, -3.0f, 1.2f}, {3.0f, -3.0f, 1.2f}, {3.0f, 3.0f, 1.2f}, {-3.0f, 3.0f, 1.2f});
  const Scene p = pane.done();
  scene.materials.push_back(pane_material);
  for (size_t t = 0; t < p.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      scene.positions.push_back(p.positions[3 * t + k]);
      scene.normals.push_back(p.normals[3 * t + k]);
      scene.uvs.push_back(p.uvs[3 * t + k]);
    }
    scene.material_of.push_back(uint32_t(scene.materials.size() - 1));
  }
  scene.finalize_materials();
  return scene;
}

TEST_F(RasterTest, AlphaBlendSurfacesAreSeenThrough) {
  // A blended pane in front of everything: the map shows what lies behind it, and its
  // triangles (appended last) never appear, though they cover most of the frame.
  const Scene behind = mixed_scene();
  Material glass;
  glass.alpha_mode = AlphaMode::Blend;
  glass.base_alpha = 0.3f;
  const Scene scene = behind_a_pane(glass);
  const size_t first_pane = behind.triangle_count();
  ASSERT_FALSE(seen_by_map(scene, first_pane));
  ASSERT_TRUE(seen_by_map(scene, 0));
  Camera camera = Camera::look_at({0.3f, 0.8f, 2.6f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.9f);
  ASSERT_GT(first_hit(scene, glm::dvec3(0.3, 0.8, 2.6), glm::dvec3(-0.3, -0.8, -2.6)), first_pane);
  check_agreement(context(), scene, camera, 80, 60, 4, &behind);
}

// A MASK pane whose alpha is below its cutoff is invisible to every ray; the map drew it
// and flagged its outline instead of the edges behind it. One at or above the cutoff is solid.
TEST_F(RasterTest, AlphaMaskSurfacesBelowTheCutoffAreNotDrawn) {
  const Scene behind = mixed_scene();
  const size_t first_pane = behind.triangle_count();
  Material cut;
  cut.alpha_mode = AlphaMode::Mask;
  cut.alpha_cutoff = 0.5f;
  cut.base_alpha = 0.1f;
  const Scene invisible = behind_a_pane(cut);
  ASSERT_FALSE(seen_by_map(invisible, first_pane));
  Camera camera = Camera::look_at({0.3f, 0.8f, 2.6f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.9f);
  check_agreement(context(), invisible, camera, 80, 60, 4, &behind);
  cut.base_alpha = 0.9f;
  EXPECT_TRUE(seen_by_map(behind_a_pane(cut), first_pane));
  // At the cutoff exactly a texel is opaque (glTF: alpha >= cutoff; render/surface_material.h):
  // the map must see it. Mutation testing: `<=` for `<` in seen_by_map changed no test.
  cut.base_alpha = cut.alpha_cutoff;
  EXPECT_TRUE(seen_by_map(behind_a_pane(cut), first_pane));
}

// A camera's clipping planes (glTF znear / zfar) cut the raster as they cut the rays
// (ids.vert with ZZ_CLIP_PLANES): what lies nearer than znear or beyond zfar is not drawn,
// and what it hid shows. Mutation testing: either gl_ClipDistance made constant changed no
// gpu test. A near quad over x < 0 at depth 1 (triangles 1, 2) before a far quad over the
// whole view at depth 3 (triangles 3, 4).
TEST_F(RasterTest, TheCamerasPlanesClipTheIds) {
  if (!context().clip_distance()) GTEST_SKIP() << "the device cannot clip";
  SceneBuilder b;
  const float X = 20.0f;
  b.quad({-X, -X, -1.0f}, {0.0f, -X, -1.0f}, {0.0f, X, -1.0f}, {-X, X, -1.0f});
  b.quad({-X, -X, -3.0f}, {X, -X, -3.0f}, {X, X, -3.0f}, {-X, X, -3.0f});
  const Scene scene = b.done();
  VisibilityPass pass(context(), scene);
  const int w = 32, h = 24, S = 4, sw = w * S + 2;
  auto ids_with = [&](float znear, float zfar) {
    Camera camera = Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f);
    camera.znear = znear;
    camera.zfar = zfar;
    return pass.render_ids(camera, w, h, {});
  };
  // Sample column u - 1 of the frame lies left of x = 0 for u - 1 < w S / 2 = 64.
  auto left = [&](size_t k) { return int(k % sw) - 1 < w * S / 2; };
  const std::vector<uint32_t> plain = ids_with(0.0f, std::numeric_limits<float>::infinity());
  const std::vector<uint32_t> near_cut = ids_with(2.0f, std::numeric_limits<float>::infinity());
  const std::vector<uint32_t> far_cut = ids_with(0.0f, 2.0f);
  for (size_t k = 0; k < plain.size(); ++k) {
    ASSERT_NE(plain[k], 0u) << "unclipped, sample " << k;
    ASSERT_EQ(plain[k] <= 2, left(k)) << "unclipped, sample " << k;
    ASSERT_GE(near_cut[k], 3u) << "znear 2 cuts the near quad away, sample " << k;
    ASSERT_EQ(far_cut[k], left(k) ? plain[k] : 0u) << "zfar 2 cuts the far quad away, sample " << k;
  }
}

// Only a BLEND material, or a MASK one below its cutoff, keeps a triangle out of the map: a
// triangle without a material entry, or whose index lies past the scene's materials, is
// drawn (the tracer hits it as any other). Mutation testing: either case not drawn changed
// no test; the map then misses that geometry's edges and flags what it hides.
TEST(SeenByMap, ATriangleWithoutAValidMaterialIsDrawn) {
  SceneBuilder b;
  b.tri({0.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -1.0f}, {0.0f, 1.0f, -1.0f});
  b.tri({0.0f, 0.0f, -2.0f}, {1.0f, 0.0f, -2.0f}, {0.0f, 1.0f, -2.0f});
  b.tri({0.0f, 0.0f, -3.0f}, {1.0f, 0.0f, -3.0f}, {0.0f, 1.0f, -3.0f});
  Scene scene = b.done();
  scene.material_of = {0u, uint32_t(scene.materials.size())};  // triangle 2 has no entry
  EXPECT_TRUE(seen_by_map(scene, 0));
  EXPECT_TRUE(seen_by_map(scene, 1)) << "a material index past the scene's materials";
  EXPECT_TRUE(seen_by_map(scene, 2)) << "no material entry";
}

TEST_F(RasterTest, IdsMatchFarFromWorldOrigin) {
  // Camera-relative transforms keep agreement when everything sits at 1e4.
  SceneBuilder b;
  glm::vec3 o(1e4f, -2e4f, 1e4f);
  b.sphere(o, 1.0f, 40, 20);
  b.box(o + glm::vec3(0.8f, -1.0f, -1.0f), o + glm::vec3(1.6f, 0.5f, 0.0f));
  Camera camera = Camera::look_at(o + glm::vec3(0.5f, 0.5f, 4.0f), o, {0, 1, 0}, 0.8f);
  check_agreement(context(), b.done(), camera, 64, 48, 4);
}

TEST_F(RasterTest, IdsMatchAtExtremeDistances) {
  // Reverse-Z with a tiny near plane: a 1e-4 triangle at 1e-4 and a wall at 1e6.
  SceneBuilder b;
  b.tri({-0.5e-4f, -0.5e-4f, -1e-4f}, {0.5e-4f, -0.5e-4f, -1e-4f}, {0.0f, 0.5e-4f, -1.2e-4f});
  b.quad({-1e7f, -1e7f, -1e6f}, {1e7f, -1e7f, -1.1e6f}, {1e7f, 1e7f, -1e6f}, {-1e7f, 1e7f, -0.9e6f});
  Camera camera = Camera::look_at({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0, 1, 0}, 0.8f);
  check_agreement(context(), b.done(), camera, 48, 40, 4);
}

// An orthographic view's linear depth range reaches past the farthest corner of the scene
// (1.01 of it): a wall square to the view as the farthest geometry, every sample on it at
// that depth, is drawn, not lost at the far end of the range. Mutation testing: the range
// ending at the farthest corner itself changed no test.
TEST_F(RasterTest, AnOrthographicViewDrawsAWallAtTheFarEndOfTheScene) {
  SceneBuilder b;
  b.quad({-20.0f, -20.0f, -5.0f}, {20.0f, -20.0f, -5.0f}, {20.0f, 20.0f, -5.0f}, {-20.0f, 20.0f, -5.0f});
  const Scene scene = b.done();
  Camera camera = Camera::look_at({0.3f, -0.2f, 0.0f}, {0.3f, -0.2f, -1.0f}, {0, 1, 0}, 0.8f);
  camera.ymag = 2.0f;
  VisibilityPass pass(context(), scene);
  for (uint32_t id : pass.render_ids(camera, 16, 12)) ASSERT_NE(id, 0u) << "the wall fills the view";
}

}  // namespace
}  // namespace zz::test
