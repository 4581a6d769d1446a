// Denormals: the worker threads render with flush-to-zero and denormals-are-zero
// (core/fp_mode.h), and scenes whose radiance is denormal (lights of 1e-38, strongly
// absorbing glass) give finite, non-negative images. The speed comparison lives in
// tools/bench_denormals (no timing in unit tests).
#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <cfloat>
#include <cmath>
#include <thread>

#include "core/fp_mode.h"
#include "robust_scenes.h"

namespace zz {
namespace {

// MXCSR without its six sticky exception flags (bits 0-5): the control bits the guard owns.
unsigned mxcsr_control() { return _mm_getcsr() & ~0x3Fu; }

float denormal_product(float a, float b) {
  volatile float x = a, y = b;  // no constant folding
  return x * y;
}

TEST(FpMode, ScopedFlushDenormalsSetsAndRestoresMxcsr) {
  const unsigned before = mxcsr_control();
  EXPECT_GT(denormal_product(FLT_MIN, 0.5f), 0.0f);  // denormal result kept by default
  {
    ScopedFlushDenormals guard;
    EXPECT_TRUE(denormals_flushed());
    EXPECT_EQ(denormal_product(FLT_MIN, 0.5f), 0.0f);  // FTZ
    volatile float tiny = std::numeric_limits<float>::denorm_min();
    EXPECT_EQ(denormal_product(tiny, 1.0f), 0.0f);     // DAZ: the input reads as 0
  }
  EXPECT_EQ(mxcsr_control(), before);
}

TEST(FpMode, EveryTileRunsWithDenormalsFlushed) {
  // tile_done runs on the worker thread inside the tile task.
  std::atomic<int> tiles{0}, flushed{0};
  RenderCallbacks cb;
  cb.tile_done = [&](const TileRect&, const RayCounters&) {
    ++tiles;
    flushed += denormals_flushed();
  };
  const unsigned before = mxcsr_control();
  for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
    RenderSettings s = robust::settings(200, 130, aa, 2);
    s.tile_size = 16;
    robust::render(robust::shadow_scene({}), s, nullptr, cb);
  }
  EXPECT_GT(tiles.load(), 100);
  EXPECT_EQ(flushed.load(), tiles.load()) << "tile tasks must run under ScopedFlushDenormals";
  EXPECT_EQ(mxcsr_control(), before) << "the caller's floating-point mode must be restored";
}

Scene denormal_scene(float light) {
  Scene s = robust::shadow_scene({});
  s.lights[0].intensity = glm::vec3(light);
  Material glass = test::glass_material(1.5f);
  glass.attenuation_color = glm::vec3(1e-6f);
  glass.attenuation_distance = 1e-3f;  // sigma = 1.4e4 per unit: exp(-sigma d) underflows
  s.materials.push_back(glass);
  test::add_box(s, {2, -3, 0}, {4, -1, 2}, 2);
  s.background = glm::vec3(1e-38f);
  s.max_depth = 6;
  s.finalize_materials();
  return s;
}

TEST(FpMode, DenormalScenesGiveFiniteImages) {
  for (float light : {1e-38f, 1e-30f, 1.0f}) {
    for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
      const Film f = robust::render(denormal_scene(light), robust::settings(48, 32, aa));
      EXPECT_EQ(robust::bad_values(f), 0u) << light;
      // Flush-to-zero at work (review: finite values held without it too): a subnormal light
      // (1e-38) reads as 0, and no product the shading makes stays subnormal.
      size_t subnormal = 0;
      for (const glm::vec3& p : f.radiance)
        for (int c = 0; c < 3; ++c) subnormal += std::fpclassify(p[c]) == FP_SUBNORMAL;
      EXPECT_EQ(subnormal, 0u) << light;
      if (light < FLT_MIN) {
        for (const glm::vec3& p : f.radiance) EXPECT_EQ(p, glm::vec3(0.0f)) << light;
      }
    }
  }
}

}  // namespace
}  // namespace zz
