// The renderer's sample signatures (scene_source.h, aa/signature.h): what each lane saw.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "aa/adaptive_pixel.h"
#include "render/renderer.h"
#include "render/scene_source.h"
#include "test_scenes.h"

namespace zz {
namespace {

// Colour and signature of four image-plane points of a W x H frame of the scene's camera.
struct Probe {
  Rgb4 colour;
  int4 signature;
};
Probe probe(const Scene& scene, unsigned parts, float4 px, float4 py, int w, int h) {
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const CameraRays rays(scene.cameras[0], w, h);
  SceneSource source(shader, rays, parts);
  Probe p;
  p.colour = source.sample4(px, py, p.signature);
  return p;
}

// A floor lit by two equal directional lights from the left and the right at the same
// elevation, with a wall along y between them: left of the wall the right light is
// blocked, right of it the left one. A camera straight above sees both halves equally bright.
Scene two_shadows() {
  Scene s = test::lit_floor(0.5f, 0.0f, 3.0f);
  s.lights.clear();
  for (float side : {-1.0f, 1.0f}) {
    Light l;
    l.type = Light::Type::Directional;
    l.direction = glm::normalize(glm::vec3(-side, 0.0f, -1.0f));  // shines from x = side
    l.intensity = glm::vec3(2.0f);
    s.lights.push_back(l);
  }
  test::add_box(s, {-0.05f, -10.0f, 0.0f}, {0.05f, 10.0f, 1.0f}, 0);
  s.cameras[0] = Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 1.2f);
  s.finalize_materials();
  return s;
}

TEST(SceneSignature, EqualColoursButDifferentShadowingLightsDiffer) {
  const Scene s = two_shadows();
  // 64 x 64 frame: the wall is the middle column; lanes 0/1 mirror each other at x 20/44,
  // both in one light's shadow (the wall is 1 high, the lights at 45 degrees); lanes 2/3
  // far out on both sides, lit by both.
  const float4 px(20.5f, 43.5f, 2.5f, 61.5f), py(32.0f);
  const Probe all = probe(s, kSignatureAll, px, py, 64, 64);
  ASSERT_GT(all.colour.g[0], 0.0f);
  EXPECT_NEAR(all.colour.g[0], all.colour.g[1], 1e-5f * all.colour.g[0]);  // equal colours...
  EXPECT_LT(all.colour.g[0], 0.75f * all.colour.g[2]);                    // ...in one light's shadow
  EXPECT_NEAR(all.colour.g[2], all.colour.g[3], 1e-5f * all.colour.g[2]);
  EXPECT_NE(all.signature[0], all.signature[1]);  // ...but different lights blocked
  EXPECT_NE(all.signature[0], all.signature[2]);
  EXPECT_EQ(all.signature[2], all.signature[3]);  // nothing blocked on either side
  const Probe lights = probe(s, kSignatureLights, px, py, 64, 64);
  EXPECT_NE(lights.signature[0], lights.signature[1]);
  // Without the lights part the floor is one object everywhere.
  const Probe object = probe(s, kSignatureObject | kSignatureSecondary, px, py, 64, 64);
  EXPECT_EQ(object.signature[0], object.signature[1]);
  EXPECT_EQ(object.signature[0], object.signature[2]);
  // So the discontinuity predicate fires on the pair with signatures and not without.
  const float4 eps(0.05f);
  const ToneMap tm;
  const Rgb4 d = tm.apply4(all.colour);
  EXPECT_EQ(discontinuous4(d, all.signature, shuffle4<1, 0, 3, 2>(d), shuffle4<1, 0, 3, 2>(all.signature), eps) & 1, 1);
  EXPECT_EQ(discontinuous4(d, int4(0), shuffle4<1, 0, 3, 2>(d), int4(0), eps) & 1, 0);
}

// The same floor with the right-hand light so faint that it cannot move the display by
// an 8-bit step: left of the wall, in its shadow, the floor is as the open floor further
// left; right of the wall, in the bright left light's shadow, it differs from the open floor.
TEST(SceneSignature, AShadowCountsOnlyWhereItsLightCouldShow) {
  const float4 px(20.5f, 43.5f, 2.5f, 61.5f), py(32.0f);
  const auto against_open_floor = [&](const Scene& s) {
    const int4 sig = probe(s, kSignatureLights, px, py, 64, 64).signature;
    return signatures_differ4(sig, shuffle4<2, 3, 0, 1>(sig)) & 0b0011;  // lane 0 vs 2, lane 1 vs 3
  };
  EXPECT_EQ(against_open_floor(two_shadows()), 0b0011);
  Scene faint = two_shadows();
  faint.lights[1].intensity = glm::vec3(1e-4f);
  EXPECT_EQ(against_open_floor(faint), 0b0010);
}

TEST(SceneSignature, TrianglesOfOneSmoothMeshShareASignature) {
  Scene s;
  s.materials.push_back(test::diffuse_material(glm::vec3(0.7f)));
  test::add_uv_sphere(s, 12, 8, 0.3f, 0);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::normalize(glm::vec3(-0.3f, -0.4f, -1.0f));
  l.intensity = glm::vec3(3.0f);
  s.lights.push_back(l);
  s.cameras.push_back(Camera::look_at({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 0.6f));
  s.finalize_materials();
  // Four points across the lit front of the sphere, on different facets.
  const float4 px(40.0f, 64.0f, 80.0f, 58.0f), py(50.0f, 64.0f, 70.0f, 85.0f);
  const Bvh bvh = Bvh::build(s.positions);
  HitPacket4 hits;
  RayPacket4 rays;
  const CameraRays cam(s.cameras[0], 128, 128);
  rays.ox = float4(cam.origin.x), rays.oy = float4(cam.origin.y), rays.oz = float4(cam.origin.z);
  cam.directions4(px, py, rays.dx, rays.dy, rays.dz);
  rays.tmax = float4(kInfinity);
  bvh.intersect4(rays, mask4(true), hits);
  for (int i = 0; i < 4; ++i) {
    ASSERT_GE(hits.prim[i], 0);
    for (int j = 0; j < i; ++j) ASSERT_NE(hits.prim[i], hits.prim[j]) << "lanes " << i << ", " << j;
  }
  const Probe p = probe(s, kSignatureAll, px, py, 128, 128);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(p.signature[i], p.signature[0]);
  // The background is another object.
  const Probe miss = probe(s, kSignatureObject, float4(1.0f), float4(1.0f), 128, 128);
  EXPECT_NE(miss.signature[0], p.signature[0]);
}

TEST(SceneSignature, MirrorImagesOfDifferentObjectsDiffer) {
  // A mirror floor reflects a red box on the left and a green one on the right: the floor
  // is one object, what its reflection rays hit is not.
  Scene s = test::lit_floor(0.5f, 60.0f, 3.0f);
  s.materials[0] = test::mirror_material(glm::vec3(0.9f));
  s.materials.push_back(test::diffuse_material({0.8f, 0.1f, 0.1f}));
  s.materials.push_back(test::diffuse_material({0.1f, 0.8f, 0.1f}));
  test::add_box(s, {-3.0f, -1.0f, 0.0f}, {-1.0f, 1.0f, 8.0f}, 1);
  test::add_box(s, {1.0f, -1.0f, 0.0f}, {3.0f, 1.0f, 8.0f}, 2);
  s.cameras[0] = Camera::look_at({0, -6, 3}, {0, 0, 0}, {0, 0, 1}, 0.8f);
  s.finalize_materials();
  // Floor points in front of each box, where the mirror shows the box (found by tracing).
  const Scene& scene = s;
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  const CameraRays rays(scene.cameras[0], 64, 64);
  SceneSource source(shader, rays, kSignatureAll);
  // Probe the same floor row, left and right of the image centre.
  int4 sig_all, sig_object;
  const float4 px(18.0f, 46.0f, 18.0f, 46.0f), py(50.0f);
  source.sample4(px, py, sig_all);
  SceneSource object_only(shader, rays, kSignatureObject);
  object_only.sample4(px, py, sig_object);
  EXPECT_EQ(sig_object[0], sig_object[1]);  // both on the mirror floor
  EXPECT_NE(sig_all[0], sig_all[1]);        // seeing different boxes in it
  EXPECT_EQ(sig_all[0], sig_all[2]);        // lane-independent: same point, same signature
}

// A mirror floor, a mirror wall at y = 4 facing it, and behind the camera a red box left and
// a green one right: camera rays hit the floor, its reflection rays the wall, and the
// wall's reflection rays the boxes. `floor_reflectance` is the floor's metal base colour.
Scene mirror_in_mirror(float floor_reflectance) {
  Scene s = test::lit_floor(0.5f, 60.0f, 3.0f);
  s.materials[0] = test::mirror_material(glm::vec3(floor_reflectance));
  s.materials.push_back(test::mirror_material(glm::vec3(0.9f)));
  s.materials.push_back(test::diffuse_material({0.8f, 0.1f, 0.1f}));
  s.materials.push_back(test::diffuse_material({0.1f, 0.8f, 0.1f}));
  test::add_quad(s, {-30, 4, -1}, {-30, 4, 40}, {30, 4, 40}, {30, 4, -1}, 1);
  test::add_box(s, {-40.0f, -16.0f, -1.0f}, {0.0f, -12.0f, 60.0f}, 2);
  test::add_box(s, {0.0f, -16.0f, -1.0f}, {40.0f, -12.0f, 60.0f}, 3);
  s.cameras[0] = Camera::look_at({0, -6, 3}, {0, 0, 0}, {0, 0, 1}, 0.8f);
  s.finalize_materials();
  return s;
}

TEST(SceneSignature, AMirrorSeenInAMirrorSignsWhatItShows) {
  // Chrome reflecting chrome (the car's bumper): the first reflection hits the same wall
  // left and right, the second different boxes; with both mirrors bright that shows.
  const float4 px(18.0f, 46.0f, 18.0f, 46.0f), py(50.0f);
  const Probe bright = probe(mirror_in_mirror(0.9f), kSignatureSecondary, px, py, 64, 64);
  EXPECT_GT(bright.colour.r[0], 2.0f * bright.colour.g[0]);  // the red box, twice reflected
  EXPECT_GT(bright.colour.g[1], 2.0f * bright.colour.r[1]);  // the green one
  EXPECT_NE(bright.signature[0], bright.signature[1]);
  EXPECT_EQ(bright.signature[0], bright.signature[2]);  // same point, same signature
  // A dim floor passes under half the light on to the wall (kSignedMirrorPath): what the
  // wall shows through it is left to the colour comparison.
  const Probe dim = probe(mirror_in_mirror(0.3f), kSignatureSecondary, px, py, 64, 64);
  EXPECT_GT(dim.colour.r[0], 2.0f * dim.colour.g[0]);
  EXPECT_EQ(dim.signature[0], dim.signature[1]);
}

TEST(SceneSignature, SignaturesDoNotChangeTheImageOrTheRays) {
  // Signatures are bookkeeping: the same colours and ray counts, whatever the parts.
  const Scene s = two_shadows();
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  const CameraRays rays(s.cameras[0], 32, 32);
  SceneSource plain(shader, rays), signed_source(shader, rays, kSignatureAll);
  for (float y = 0.5f; y < 32.0f; y += 3.0f) {
    const float4 px(0.5f, 7.5f, 16.5f, 29.5f), py(y);
    const Rgb4 a = plain.sample4(px, py);
    int4 sig;
    const Rgb4 b = signed_source.sample4(px, py, sig);
    EXPECT_EQ((a.r == b.r).bits() & (a.g == b.g).bits() & (a.b == b.b).bits(), 0xF);
  }
  EXPECT_EQ(plain.counters.total(), signed_source.counters.total());
  EXPECT_EQ(plain.counters.shadow, signed_source.counters.shadow);
}

// lights_shown decides most lanes from the tone map's slope; whatever it decides must be
// what tone-mapping both ends says: colours from black to far past white, lights from
// invisible to dominant, reached or blocked, at three exposures.
TEST(SceneSignature, LightsShownAgreesWithToneMappingBothEnds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto magnitude = [&] { return std::pow(10.0f, -5.0f + 7.0f * unit(rng)); };  // 1e-5 .. 1e2
  int bounded = 0, shown = 0, total = 0;
  for (float exposure : {0.3f, 1.0f, 4.0f}) {
    const ToneMap tm{exposure};
    for (int round = 0; round < 4000; ++round) {
      glm::vec3 colour[4], light[kLightSlots][4];
      uint32_t shadowed[4];
      for (int i = 0; i < 4; ++i) {
        colour[i] = unit(rng) < 0.05f ? glm::vec3(0.0f) : glm::vec3(magnitude(), magnitude(), magnitude());
        shadowed[i] = uint32_t(rng()) & ((1u << kLightSlots) - 1u);
        for (int l = 0; l < kLightSlots; ++l) {
          const float k = unit(rng) < 0.2f ? 0.0f : magnitude();
          light[l][i] = k * glm::vec3(unit(rng), unit(rng), unit(rng));
          // A reached light is part of the colour: at most all of it.
          if (!((shadowed[i] >> l) & 1u)) light[l][i] = glm::min(light[l][i], colour[i] * unit(rng) * 1.2f);
        }
      }
      const Rgb4 c{float4(colour[0].r, colour[1].r, colour[2].r, colour[3].r),
                   float4(colour[0].g, colour[1].g, colour[2].g, colour[3].g),
                   float4(colour[0].b, colour[1].b, colour[2].b, colour[3].b)};
      uint32_t shows[4] = {};
      lights_shown(tm, c, light, shadowed, shows);
      // Told that only the first slots hold lights, it decides those slots the same and
      // leaves the others clear.
      const int slots = 1 + round % kLightSlots;
      uint32_t first_shows[4] = {};
      lights_shown(tm, c, light, shadowed, first_shows, slots);
      for (int i = 0; i < 4; ++i) ASSERT_EQ(first_shows[i], shows[i] & ((1u << slots) - 1u)) << slots;
      for (int i = 0; i < 4; ++i)
        for (int l = 0; l < kLightSlots; ++l) {
          const glm::vec3 a = colour[i], d = light[l][i];
          const bool lit = d.r > 0.0f || d.g > 0.0f || d.b > 0.0f;
          const bool blocked = (shadowed[i] >> l) & 1u;
          const glm::vec3 other = !lit ? a : blocked ? a + d : glm::max(a - d, glm::vec3(0.0f));
          bool want = false;
          for (int ch = 0; ch < 3; ++ch)
            want |= std::fabs(tm.apply(other[ch]) - tm.apply(a[ch])) >= kDisplayStep;
          const bool got = (shows[i] >> l) & 1u;
          ASSERT_EQ(got, want) << "exposure " << exposure << " colour " << a.r << "," << a.g << "," << a.b
                               << " light " << d.r << "," << d.g << "," << d.b << " blocked " << blocked;
          ++total;
          shown += want;
          // How often the slope's bound alone could decide (for the record, not the contract).
          const float s = std::max({tm.slope4(float4(a.r))[0] * std::fabs(other.r - a.r),
                                    tm.slope4(float4(a.g))[0] * std::fabs(other.g - a.g),
                                    tm.slope4(float4(a.b))[0] * std::fabs(other.b - a.b)});
          bounded += blocked ? s < kDisplayStep / kBoundMargin : s >= kDisplayStep * kBoundMargin;
        }
    }
  }
  // Both answers occur often, and the bounds decide a good share on their own.
  EXPECT_GT(shown, total / 5);
  EXPECT_LT(shown, total * 4 / 5);
  EXPECT_GT(bounded, total / 4);
}

}  // namespace
}  // namespace zz
