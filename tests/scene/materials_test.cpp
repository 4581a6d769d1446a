#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene/materials.h"

namespace zz {
namespace {

void expect_vec(glm::vec3 a, glm::vec3 b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

Material make(glm::vec3 base, float metallic, float roughness, float transmission = 0.0f) {
  Material m;
  m.base_color = base;
  m.metallic = metallic;
  m.roughness = roughness;
  m.transmission = transmission;
  return m;
}

const glm::vec3 kRed(0.8f, 0.2f, 0.1f);

TEST(WhittedFromGltf, RoughDielectricIsPureLambert) {
  WhittedMaterial w = whitted_from_gltf(make(kRed, 0.0f, 1.0f));
  expect_vec(w.diffuse, kRed);
  expect_vec(w.specular, glm::vec3(0.04f));  // F0 of ior 1.5
  EXPECT_FALSE(w.reflects());
  EXPECT_FALSE(w.transmits());
  EXPECT_FLOAT_EQ(w.shininess, 1.0f);  // alpha = 1 -> n = 2/1 - 2 = 0, clamped to 1
}

TEST(WhittedFromGltf, SmoothDielectricMirrorsWithFresnel) {
  WhittedMaterial w = whitted_from_gltf(make(kRed, 0.0f, 0.0f));
  expect_vec(w.diffuse, kRed);
  expect_vec(w.mirror, glm::vec3(0.04f));
  EXPECT_TRUE(w.fresnel_mirror);
  // Half way to the mirror limit: half the mirror weight.
  WhittedMaterial h = whitted_from_gltf(make(kRed, 0.0f, 0.5f * kMirrorRoughnessLimit));
  expect_vec(h.mirror, glm::vec3(0.02f));
}

TEST(WhittedFromGltf, PolishedMetalMirrorsItsBaseColour) {
  WhittedMaterial w = whitted_from_gltf(make(kRed, 1.0f, 0.0f));
  expect_vec(w.diffuse, glm::vec3(0.0f));
  expect_vec(w.mirror, kRed);
  expect_vec(w.specular, kRed);
  EXPECT_FALSE(w.fresnel_mirror);
  WhittedMaterial half = whitted_from_gltf(make(kRed, 1.0f, 0.1f));
  expect_vec(half.mirror, kRed * 0.5f, 1e-5f);
  WhittedMaterial rough = whitted_from_gltf(make(kRed, 1.0f, kMirrorRoughnessLimit));
  EXPECT_FALSE(rough.reflects());
}

TEST(WhittedFromGltf, PartialMetalMixesBothMirrors) {
  WhittedMaterial w = whitted_from_gltf(make(kRed, 0.5f, 0.0f));
  const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), kRed, 0.5f);
  expect_vec(w.mirror, f0 * 0.5f + glm::vec3(0.04f * 0.5f));
  expect_vec(w.diffuse, kRed * 0.5f);
}

TEST(WhittedFromGltf, TransmissionBendsWithIorAndReflectsFresnel) {
  Material m = make(glm::vec3(0.9f, 1.0f, 0.8f), 0.0f, 0.7f, 1.0f);
  m.ior = 1.33f;
  WhittedMaterial w = whitted_from_gltf(m);
  expect_vec(w.transmission, m.base_color);
  expect_vec(w.diffuse, glm::vec3(0.0f));
  EXPECT_FLOAT_EQ(w.ior, 1.33f);
  const float f0 = std::pow((1.33f - 1.0f) / (1.33f + 1.0f), 2.0f);
  expect_vec(w.mirror, glm::vec3(f0), 1e-6f);  // rough or not, glass mirrors
  EXPECT_TRUE(w.fresnel_mirror);
  // Half transmissive: the other half stays diffuse.
  WhittedMaterial half = whitted_from_gltf(make(kRed, 0.0f, 1.0f, 0.5f));
  expect_vec(half.diffuse, kRed * 0.5f);
  expect_vec(half.transmission, kRed * 0.5f);
  // Metal does not transmit.
  EXPECT_FALSE(whitted_from_gltf(make(kRed, 1.0f, 0.0f, 1.0f)).transmits());
}

TEST(WhittedFromGltf, InvalidIorFallsBackTo15) {
  Material m = make(glm::vec3(1.0f), 0.0f, 0.0f, 1.0f);
  m.ior = std::nanf("");
  EXPECT_FLOAT_EQ(whitted_from_gltf(m).ior, 1.5f);
  m.ior = 0.5f;
  EXPECT_FLOAT_EQ(whitted_from_gltf(m).ior, 1.5f);
}

// ior 1 is a valid index (KHR_materials_ior: ior >= 1; out_of_range_factors does not name
// it): kept, a transmissive surface that does not bend light and mirrors nothing (F0 = 0).
TEST(WhittedFromGltf, AnIorOfOneIsKept) {
  Material m = make(glm::vec3(1.0f), 0.0f, 0.0f, 1.0f);
  m.ior = 1.0f;
  const WhittedMaterial w = whitted_from_gltf(m);
  EXPECT_EQ(w.ior, 1.0f);
  expect_vec(w.mirror, glm::vec3(0.0f));
  EXPECT_TRUE(out_of_range_factors(m).empty());
}

// Clear glass (KHR_materials_transmission 1) with a volume: `thickness`, `attenuation` at a
// distance of 2.
Material absorbing_glass(glm::vec3 attenuation, float thickness = 1.0f) {
  Material m = make(glm::vec3(1.0f), 0.0f, 0.0f, 1.0f);
  m.thickness = thickness;
  m.attenuation_color = attenuation;
  m.attenuation_distance = 2.0f;
  return m;
}

// An attenuation colour above 1 is clamped to 1 (as out_of_range_factors reports): that
// channel does not absorb, and no channel gains light along the path (sigma_a < 0).
TEST(WhittedFromGltf, AnAttenuationColourAboveOneDoesNotAmplify) {
  const WhittedMaterial w = whitted_from_gltf(absorbing_glass(glm::vec3(4.0f, 1.0f, 0.5f)));
  expect_vec(w.absorption, glm::vec3(0.0f, 0.0f, std::log(2.0f) / 2.0f));
}

TEST(WhittedFromGltf, VolumeAttenuationIsBeerLambert) {
  const WhittedMaterial w = whitted_from_gltf(absorbing_glass(glm::vec3(0.5f, 0.25f, 1.0f), 0.5f));
  EXPECT_FALSE(w.thin_walled);
  // sigma_a = -ln(c) / d, so exp(-sigma_a * d) = c.
  expect_vec(w.absorption, glm::vec3(std::log(2.0f) / 2.0f, std::log(4.0f) / 2.0f, 0.0f));
  Material clear = make(glm::vec3(1.0f), 0.0f, 0.0f, 1.0f);
  clear.thickness = 0.5f;
  expect_vec(whitted_from_gltf(clear).absorption, glm::vec3(0.0f));  // infinite distance
}

// KHR_materials_volume: without it, or at thicknessFactor 0 (its default), the material
// is thin-walled: no volume, so nothing to absorb, whatever the attenuation says.
TEST(WhittedFromGltf, WithoutAThicknessTransmissionIsThinWalled) {
  Material m = make(glm::vec3(1.0f), 0.0f, 0.0f, 1.0f);
  EXPECT_TRUE(whitted_from_gltf(m).thin_walled);
  m.attenuation_color = glm::vec3(0.5f);
  m.attenuation_distance = 2.0f;
  const WhittedMaterial w = whitted_from_gltf(m);
  EXPECT_TRUE(w.thin_walled);
  expect_vec(w.absorption, glm::vec3(0.0f));
  m.thickness = 1e-3f;
  EXPECT_FALSE(whitted_from_gltf(m).thin_walled);
}

TEST(WhittedFromGltf, ShininessFollowsGgxAlpha) {
  // alpha = r^2 = 0.25 -> n = 2 / alpha^2 - 2 = 30.
  EXPECT_NEAR(whitted_from_gltf(make(kRed, 0.0f, 0.5f)).shininess, 30.0f, 1e-3f);
  EXPECT_FLOAT_EQ(whitted_from_gltf(make(kRed, 0.0f, 0.0f)).shininess, 10000.0f);  // clamped
}

// An attenuation colour with a black channel absorbs that channel strongly, but finitely:
// the colour is clamped to 1e-6 before its logarithm (an infinite sigma_a would be NaN
// through 0 x inf at a zero path length).
TEST(WhittedFromGltf, ABlackAttenuationChannelAbsorbsFinitely) {
  const WhittedMaterial w = whitted_from_gltf(absorbing_glass(glm::vec3(0.0f, 0.5f, 1.0f)));
  EXPECT_NEAR(w.absorption.x, -std::log(1e-6f) / 2.0f, 1e-4f);
  EXPECT_NEAR(w.absorption.y, std::log(2.0f) / 2.0f, 1e-6f);
}

TEST(WhittedFromGltf, EmissionIsNonNegativeAndOutOfRangeInputsClamp) {
  Material m = make(glm::vec3(2.0f, -1.0f, 0.5f), 3.0f, -1.0f);
  m.emissive = glm::vec3(1.0f, -2.0f, 0.0f);
  WhittedMaterial w = whitted_from_gltf(m);
  expect_vec(w.emission, glm::vec3(1.0f, 0.0f, 0.0f));
  expect_vec(w.mirror, glm::vec3(1.0f, 0.0f, 0.5f));  // metallic 1, roughness 0 after clamping
}

// What whitted_from_gltf clamps or replaces is named, so the loaders can say so.
TEST(OutOfRangeFactors, NameEachFactorGltfForbids) {
  EXPECT_TRUE(out_of_range_factors(Material{}).empty());
  EXPECT_TRUE(out_of_range_factors(make(glm::vec3(0.0f), 1.0f, 0.0f, 1.0f)).empty());  // the bounds are allowed
  Material m = make(glm::vec3(2.0f, -1.0f, 0.5f), 3.0f, -1.0f, 1.5f);
  m.base_alpha = -0.5f;
  m.emissive = glm::vec3(1.0f, -2.0f, 0.0f);
  m.ior = 0.5f;
  m.attenuation_distance = 0.0f;
  m.attenuation_color = glm::vec3(1.5f, 0.5f, 0.5f);
  m.thickness = -1.0f;
  const std::vector<std::string> want = {"base colour (2, -1, 0.5) outside [0, 1], clamped",
                                         "alpha -0.5 outside [0, 1], clamped",
                                         "metallic 3 outside [0, 1], clamped",
                                         "roughness -1 outside [0, 1], clamped",
                                         "transmission 1.5 outside [0, 1], clamped",
                                         "attenuation colour (1.5, 0.5, 0.5) outside [0, 1], clamped",
                                         "emissive (1, -2, 0) below 0, clamped",
                                         "ior 0.5 below 1, 1.5 used",
                                         "thickness -1 below 0, thin-walled, as 0",
                                         "attenuation distance 0 not > 0, no absorption"};
  std::vector<std::string> got;
  for (const FactorProblem& f : out_of_range_factors(m)) got.push_back(f.text());
  EXPECT_EQ(got, want);
  // Emission beyond where the shader's radiance stops (a light there is an error).
  Material bright;
  bright.emissive = glm::vec3(1e38f, 1.0f, 0.0f);
  const std::vector<FactorProblem> found = out_of_range_factors(bright);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].text(), "emissive (1e+38, 1, 0) above 1e30, clamped to 1e30");
}

// KHR_materials_ior's ior 0 (a Fresnel of 1, for specular-glossiness conversions that
// KHR_materials_specular completes) is named as such, not as a value below 1.
TEST(OutOfRangeFactors, IorZeroIsNamedAsTheSpecularGlossinessConvention) {
  Material m;
  m.ior = 0.0f;
  const std::vector<FactorProblem> found = out_of_range_factors(m);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].text(),
            "ior 0 (specular-glossiness's full Fresnel, for KHR_materials_specular, which zigzag does not support), 1.5 used");
  EXPECT_EQ(whitted_from_gltf(m).ior, 1.5f);
}

// Each colour is checked at both ends, and a NaN ior or attenuation distance (which
// whitted_from_gltf replaces too) is named like one out of range.
TEST(OutOfRangeFactors, NameNegativeColoursAndNaNs) {
  Material m;
  m.base_color = glm::vec3(0.5f, -0.1f, 0.5f);
  m.attenuation_color = glm::vec3(-1.0f, 0.5f, 0.5f);
  m.ior = std::nanf("");
  m.attenuation_distance = std::nanf("");
  std::vector<std::string> got;
  for (const FactorProblem& f : out_of_range_factors(m)) got.push_back(f.what);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(got[0].rfind("base colour (0.5, -0.1, 0.5)", 0), 0u) << got[0];
  EXPECT_EQ(got[1].rfind("attenuation colour (-1, 0.5, 0.5)", 0), 0u) << got[1];
  EXPECT_EQ(got[2].rfind("ior ", 0), 0u) << got[2];
  EXPECT_EQ(got[3].rfind("attenuation distance ", 0), 0u) << got[3];
}

}  // namespace
}  // namespace zz
