// HDR: lights from 1e-6 to 1e9, black and white materials, a white mirror box with many
// bounces: no NaN, Inf or negative value in any output (radiance, the 8-bit display
// bytes a PNG holds, the EXR written to disk), and radiance linear in the light.
// Tone mapping of NaN / +-Inf / negative radiance through the whole output pipeline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <unistd.h>

#include "robust_scenes.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("zz_robust_hdr_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

// Every output of a film: radiance, display bytes, and an EXR read back.
void expect_clean_outputs(const Film& film, const ToneMap& tm, const std::string& name) {
  ASSERT_EQ(robust::bad_values(film), 0u) << name;
  const std::vector<uint8_t> bytes = display_bytes(film, tm);
  ASSERT_EQ(bytes.size(), film.radiance.size() * 3);
  const fs::path exr = temp_file(name + ".exr");
  write_film(exr, film, tm);
  int w = 0, h = 0;
  const std::vector<float> back = read_rgb_float(exr, w, h);
  ASSERT_EQ(w, film.width);
  ASSERT_EQ(h, film.height);
  size_t bad = 0;
  for (float v : back) bad += !std::isfinite(v) || v < 0.0f;
  EXPECT_EQ(bad, 0u) << name << ": EXR";
  fs::remove(exr);
}

TEST(Hdr, LightsFrom1eMinus6To1e9AreLinearAndClean) {
  // A box on a floor (shadows, silhouettes), a mirror and a glass block: every path type.
  Scene base = robust::shadow_scene({});
  Material mirror;
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  mirror.base_color = glm::vec3(0.9f);
  base.materials.push_back(mirror);
  base.materials.push_back(test::glass_material(1.5f));
  test::add_box(base, {2, -3, 0}, {3, -2, 2}, 2);
  test::add_box(base, {-3, -3, 0}, {-2, -2, 1}, 3);
  base.max_depth = 4;
  base.background = glm::vec3(0.0f);
  base.finalize_materials();
  const RenderSettings rs = robust::settings(48, 32, AaMode::Adaptive);
  Scene unit = base;
  unit.lights[0].intensity = glm::vec3(1.0f);
  const Film reference = robust::render(unit, rs);
  for (double intensity : {1e-6, 1e-3, 1.0, 1e3, 1e6, 1e9}) {
    Scene s = base;
    s.lights[0].intensity = glm::vec3(float(intensity));
    const Film f = robust::render(s, rs);
    expect_clean_outputs(f, ToneMap{}, "light_" + std::to_string(int(std::log10(intensity))));
    // Radiance is linear in the light (same paths, one multiplication). Refinement
    // depends on displayed values, so it differs between exposures: the check holds where
    // every pixel within the filter's reach (2) traced the same rays at the same level.
    auto same_decisions = [&](int x, int y) {
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int u = std::clamp(x + dx, 0, f.width - 1), v = std::clamp(y + dy, 0, f.height - 1);
          const size_t j = size_t(v) * size_t(f.width) + size_t(u);
          if (f.rays[j] != reference.rays[j] || f.level[j] != reference.level[j]) return false;
        }
      return true;
    };
    double worst = 0.0;
    int compared = 0;
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        if (!same_decisions(x, y)) continue;
        ++compared;
        const size_t i = size_t(y) * size_t(f.width) + size_t(x);
        for (int k = 0; k < 3; ++k) {
          const double expect = double(reference.radiance[i][k]) * intensity;
          worst = std::max(worst, std::abs(double(f.radiance[i][k]) - expect) / std::max(expect, 1e-30 + 1e-3 * intensity));
        }
      }
    std::printf("[ hdr ] light %-6g: %d of %d pixels decided alike, worst relative deviation from linear %.3g\n",
                intensity, compared, f.width * f.height, worst);
    EXPECT_GT(compared, f.width * f.height / 4);  // 46 % at 1e3 and brighter, where the display saturates
    EXPECT_LT(worst, 1e-5);
  }
  // Strict linearity without adaptive decisions.
  const RenderSettings none = robust::settings(48, 32, AaMode::None);
  const Film ref_none = robust::render(unit, none);
  for (double intensity : {1e-6, 1e9}) {
    Scene s = base;
    s.lights[0].intensity = glm::vec3(float(intensity));
    const Film f = robust::render(s, none);
    for (size_t i = 0; i < f.radiance.size(); ++i)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(f.radiance[i][k], ref_none.radiance[i][k] * float(intensity),
                    1e-5 * std::max(double(ref_none.radiance[i][k]) * intensity, 1e-30))
            << intensity;
  }
}

TEST(Hdr, BlackAndWhiteMaterialsWithManyBounces) {
  // A closed box of white mirrors with a bright light and a white diffuse floor inside,
  // 16 bounces; and the same box in black.
  for (float albedo : {0.0f, 1.0f}) {
    Scene s;
    Material mirror;
    mirror.metallic = 1.0f;
    mirror.roughness = 0.0f;
    mirror.base_color = glm::vec3(albedo);
    s.materials.push_back(mirror);
    s.materials.push_back(test::diffuse_material(glm::vec3(albedo)));
    Scene walls;
    test::add_box(walls, {-2, -2, -2}, {2, 2, 2}, 0);
    for (size_t t = 0; t < walls.triangle_count(); ++t)  // inward-facing: reverse winding
      test::add_triangle(s, walls.positions[3 * t], walls.positions[3 * t + 2], walls.positions[3 * t + 1], 0);
    test::add_quad(s, {-1, -1, -1.5f}, {1, -1, -1.5f}, {1, 1, -1.5f}, {-1, 1, -1.5f}, 1);
    Light l;
    l.position = {0.3f, 0.2f, 1.5f};
    l.intensity = glm::vec3(1e9f);
    s.lights.push_back(l);
    s.cameras.push_back(Camera::look_at({1.5f, -1.5f, 1.0f}, {0, 0, -1.5f}, {0, 0, 1}, 1.2f));
    s.max_depth = 16;
    s.finalize_materials();
    for (AaMode aa : {AaMode::None, AaMode::Adaptive}) {
      RenderStats st;
      const Film f = robust::render(s, robust::settings(40, 40, aa), &st);
      expect_clean_outputs(f, ToneMap{}, "box_" + std::to_string(int(albedo)));
      if (albedo > 0.0f) {
        EXPECT_GT(st.rays.reflection, 40u * 40u * 4u);  // the bounces were really traced
      }
    }
  }
}

TEST(Hdr, ToneMappingOfNanInfAndNegativeThroughThePipeline) {
  // A film holding every special value goes through display bytes (PNG) and a PNG file:
  // NaN and negatives -> 0, +Inf -> 255, huge finite -> 255.
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  Film film(6, 1);
  const float values[6] = {nan, inf, -inf, -1.0f, 3e38f, std::numeric_limits<float>::denorm_min()};
  for (int i = 0; i < 6; ++i) film.radiance[size_t(i)] = glm::vec3(values[i]);
  for (float exposure : {1.0f, 1e-20f, 1e20f}) {
    ToneMap tm;
    tm.exposure = exposure;
    const std::vector<uint8_t> b = display_bytes(film, tm);
    const int expected[6] = {0, 255, 0, 0, 255, 0};
    for (int i = 0; i < 6; ++i) {
      if (exposure < 1.0f && i == 4) continue;  // 3e38 * 1e-20 is an ordinary colour
      EXPECT_EQ(b[size_t(3 * i)], expected[i]) << "value " << values[i] << " exposure " << exposure;
    }
    for (float v : {nan, inf, -inf, -1.0f, 3e38f}) {
      const float d = tm.apply(v);
      EXPECT_TRUE(d >= 0.0f && d <= 1.0f) << v;
    }
  }
  const fs::path png = temp_file("special.png");
  write_film(png, film, ToneMap{});
  int w = 0, h = 0;
  const std::vector<float> back = read_rgb_float(png, w, h);
  ASSERT_EQ(back.size(), 18u);
  EXPECT_EQ(back[0], 0.0f);
  EXPECT_EQ(back[3], 1.0f);
  EXPECT_EQ(back[6], 0.0f);
  fs::remove(png);
}

}  // namespace
}  // namespace zz
