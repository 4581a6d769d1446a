// Rays that go on past what they hit (render/see_through.h): cut-outs, clipping planes
// and shadow rays through BLEND panes and glass, lane by lane.
#include "render/see_through.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_scenes.h"

namespace zz {
namespace {

// Panes at z = 1, 1 + pitch, ... (facing +z, 4 x 4 about the z axis) of the given
// materials, an opaque floor at z = 0 when `floor` is set; rays come down the -z axis from
// z = 30.
struct Stack {
  Scene scene;
  Bvh bvh;
  Stack(const std::vector<Material>& panes, bool floor, float pitch = 1.0f) {
    for (size_t k = 0; k < panes.size(); ++k) {
      const float z = 1.0f + float(k) * pitch;
      scene.materials.push_back(panes[k]);
      test::add_quad(scene, {-2, -2, z}, {2, -2, z}, {2, 2, z}, {-2, 2, z}, uint32_t(k));
    }
    if (floor) {
      scene.materials.push_back(test::diffuse_material(glm::vec3(0.5f)));
      test::add_quad(scene, {-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}, uint32_t(panes.size()));
    }
    scene.finalize_materials();
    bvh = Bvh::build(scene.positions);
  }
  int floor_material() const { return int(scene.materials.size()) - 1; }
};

Material blend(float alpha) {
  Material m = test::diffuse_material(glm::vec3(0.8f));
  m.alpha_mode = AlphaMode::Blend;
  m.base_alpha = alpha;
  return m;
}

Material mask(float alpha, float cutoff) {
  Material m = test::diffuse_material(glm::vec3(0.8f));
  m.alpha_mode = AlphaMode::Mask;
  m.base_alpha = alpha;
  m.alpha_cutoff = cutoff;
  return m;
}

// Four rays straight down from z = 30 at x = -1.5, -0.5, 0.5, 1.5.
RayPacket4 rays_down() {
  PacketBuilder b;
  for (int i = 0; i < 4; ++i) b.set(i, {float(i) - 1.5f, 0.0f, 30.0f}, {0.0f, 0.0f, -1.0f}, kInfinity);
  return b.packet();
}

LaneHits first_hits(const Stack& s, const RayPacket4& rays) {
  HitPacket4 h;
  s.bvh.intersect4(rays, mask4(true), h);
  return LaneHits(h);
}

// A shadow packet from just above the floor to a point light at z = 50, lanes `lanes`.
glm::vec3 light_through(const Stack& s, int lanes, int lane, RayCounters* counters = nullptr) {
  Light light;
  light.position = {0.0f, 0.0f, 50.0f};
  PacketBuilder rays;
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 origin(float(i) - 1.5f, 0.0f, 0.01f);
    rays.set(i, origin, light.position - origin, 1.0f - kShadowEpsilon);
  }
  glm::vec3 through[4];
  RayCounters local;
  shadow_transmittance<false, true, false>(s.scene, s.bvh, light, rays, lanes, through, counters ? *counters : local);
  return through[lane];
}

TEST(SeeThrough, PassCutoutsSkipsMaskedPanesAndCountsTheDistance) {
  // Pane 1 (z = 2) cut out (alpha 0.2 < cutoff 0.5), pane 0 (z = 1) covered (0.7): rays
  // from z = 30 pass the first and stop at the second, 28 units travelled through cut-outs.
  const Stack s({mask(0.7f, 0.5f), mask(0.2f, 0.5f)}, true);
  const RayPacket4 rays = rays_down();
  LaneHits hits = first_hits(s, rays);
  ASSERT_EQ(s.scene.material_of[size_t(hits.prim[0])], 1u);  // the cut-out pane first
  float skipped[4] = {};
  RayCounters counters;
  pass_cutouts(s.scene, s.bvh, rays, 0b0111, hits, skipped, counters);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(s.scene.material_of[size_t(hits.prim[i])], 0u) << i;
    EXPECT_NEAR(skipped[i], 28.0f, 1e-4f) << i;
  }
  EXPECT_EQ(s.scene.material_of[size_t(hits.prim[3])], 1u);  // inactive lane untouched
  EXPECT_EQ(skipped[3], 0.0f);
  EXPECT_EQ(counters.continuation, 3u);
}

TEST(SeeThrough, PassCutoutsGivesUpAfterTheLayerLimit) {
  // kMaxSeeThroughLayers cut-out panes are passed, one more makes the ray a miss, counted.
  static_assert(kMaxSeeThroughLayers >= 64, "foliage cards stack by the tens");
  for (const int panes : {kMaxSeeThroughLayers, kMaxSeeThroughLayers + 1}) {
    const Stack s(std::vector<Material>(size_t(panes), mask(0.0f, 0.5f)), true, 0.1f);
    const RayPacket4 rays = rays_down();
    LaneHits hits = first_hits(s, rays);
    float skipped[4] = {};
    RayCounters counters;
    pass_cutouts(s.scene, s.bvh, rays, 0b1111, hits, skipped, counters);
    if (panes == kMaxSeeThroughLayers) {
      EXPECT_EQ(int(s.scene.material_of[size_t(hits.prim[0])]), s.floor_material());
      EXPECT_EQ(counters.layer_limit, 0u);
    } else {
      EXPECT_LT(hits.prim[0], 0) << panes << " cut-out layers";
      EXPECT_EQ(counters.layer_limit, 4u);
    }
  }
}

TEST(SeeThrough, ClipNearRestartsAtThePlaneAndClipFarDropsHitsBeyondIt) {
  const Stack s({test::diffuse_material(glm::vec3(0.5f))}, true);  // pane at z = 1, floor at 0
  const RayPacket4 rays = rays_down();
  CameraClip clip;
  clip.origin = {0.0f, 0.0f, 30.0f};
  clip.forward = {0.0f, 0.0f, -1.0f};
  clip.znear = 29.5f;  // the plane at z = 0.5: the pane (depth 29) is cut away
  LaneHits hits = first_hits(s, rays);
  float skipped[4] = {};
  RayCounters counters;
  clip_near(s.scene, s.bvh, rays, 0b1111, hits, skipped, clip, counters);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(int(s.scene.material_of[size_t(hits.prim[i])]), s.floor_material()) << i;
    EXPECT_NEAR(skipped[i], 29.5f, 1e-5f) << i;
  }
  clip.zfar = 29.9f;  // the floor (depth 30) lies beyond the far plane
  clip_far(s.scene, 0b0011, hits, clip);
  EXPECT_LT(hits.prim[0], 0);
  EXPECT_LT(hits.prim[1], 0);
  EXPECT_GE(hits.prim[2], 0);  // inactive lanes are left as they were
}

TEST(SeeThrough, ShadowRaysPassBlendPanesByOneMinusAlphaEach) {
  const Stack s({blend(0.25f), blend(0.5f)}, false);
  RayCounters counters;
  const glm::vec3 t = light_through(s, 0b1111, 2, &counters);
  EXPECT_NEAR(t.r, 0.75f * 0.5f, 1e-6f);
  EXPECT_EQ(t.r, t.g);
  EXPECT_EQ(t.r, t.b);
  EXPECT_EQ(counters.shadow, 12u);  // 4 lanes x (2 panes + the last segment to the light)
  EXPECT_EQ(light_through(s, 0b0001, 2), glm::vec3(0.0f));  // an inactive lane gets nothing
}

TEST(SeeThrough, ShadowRaysStopAtOpaqueSurfacesAndAfterTheLayerLimit) {
  EXPECT_EQ(light_through(Stack({blend(0.25f), test::diffuse_material(glm::vec3(1.0f))}, false), 0b1111, 0),
            glm::vec3(0.0f));
  // Panes passing 99 % each: the light through the limit's worth is far from negligible.
  const float clear = std::pow(0.99f, float(kMaxSeeThroughLayers));
  RayCounters counters;
  EXPECT_NEAR(light_through(Stack(std::vector<Material>(size_t(kMaxSeeThroughLayers), blend(0.01f)), false, 0.1f),
                            0b1111, 1, &counters).g,
              clear, clear * 1e-4f);
  EXPECT_EQ(counters.layer_limit, 0u);
  EXPECT_EQ(light_through(Stack(std::vector<Material>(size_t(kMaxSeeThroughLayers + 1), blend(0.01f)), false, 0.1f),
                          0b1111, 1, &counters),
            glm::vec3(0.0f));
  EXPECT_EQ(counters.layer_limit, 4u);
  // An opaque surface after the limit's worth blocks the light; nothing was left out there.
  std::vector<Material> then_opaque(size_t(kMaxSeeThroughLayers), blend(0.01f));
  then_opaque.push_back(test::diffuse_material(glm::vec3(1.0f)));
  RayCounters blocked;
  EXPECT_EQ(light_through(Stack(then_opaque, false, 0.1f), 0b1111, 1, &blocked), glm::vec3(0.0f));
  EXPECT_EQ(blocked.layer_limit, 0u);
}

}  // namespace
}  // namespace zz
