// glTF material features end to end: a small synthetic glTF per feature (tests/scene/
// gltf_fixture.h) in a rig with a camera looking straight down at the z = 0 plane, whose
// 64 x 64 frame covers [-1, 1]^2; each checked numerically on the rendered image.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>

#include "../scene/gltf_fixture.h"
#include "core/error.h"
#include "render/renderer.h"
#include "scene/camera_select.h"
#include "scene/loader.h"

namespace zz {
namespace {

using nlohmann::json;
constexpr int kSize = 64;
constexpr float kPi = 3.14159265358979f;

// Pixel of world point (x, y) on the z = 0 plane.
int px(float x) { return std::clamp(int((x + 1.0f) * 0.5f * kSize), 0, kSize - 1); }
int py(float y) { return std::clamp(int((1.0f - y) * 0.5f * kSize), 0, kSize - 1); }

struct Image {
  Film film;
  glm::vec3 at(float x, float y) const { return film.radiance[size_t(py(y)) * size_t(kSize) + size_t(px(x))]; }
};

Image render_scene(const Scene& scene) {
  const Bvh bvh = Bvh::build(scene.positions);
  const Shader shader(scene, bvh);
  RenderSettings s;
  s.width = s.height = kSize;
  s.aa = AaMode::None;
  Image image;
  RenderStats stats;
  render_frame(shader, scene.cameras[0], GeoMap{}, s, image.film, stats);
  for (const glm::vec3& c : image.film.radiance)
    EXPECT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b));
  EXPECT_EQ(stats.rays.nan_radiance, 0u);  // the shader sets NaN to 0: the count is what shows it
  return image;
}

// A w x h RGBA8 PNG in `dir`, added to the glTF as image + texture with a sampler.
int add_texture(test::GltfBuilder& b, const std::filesystem::path& dir, const std::string& name, int w, int h,
                const std::vector<uint8_t>& rgba, json sampler = {{"magFilter", 9728}, {"minFilter", 9728}}) {
  auto out = OIIO::ImageOutput::create((dir / name).string());
  OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1);
  EXPECT_TRUE(out && out->open((dir / name).string(), spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgba.data()));
  out->close();
  if (!b.doc.contains("images")) b.doc["images"] = json::array(), b.doc["textures"] = json::array(), b.doc["samplers"] = json::array();
  b.doc["images"].push_back({{"uri", name}});
  b.doc["samplers"].push_back(sampler);
  b.doc["textures"].push_back({{"source", b.doc["images"].size() - 1}, {"sampler", b.doc["samplers"].size() - 1}});
  return int(b.doc["textures"].size() - 1);
}

int add_material(test::GltfBuilder& b, json m) {
  if (!b.doc.contains("materials")) b.doc["materials"] = json::array();
  b.doc["materials"].push_back(m);
  return int(b.doc["materials"].size() - 1);
}

// Quad x0..x1, y0..y1 at height z facing +z (or -z), uv = ((x + 1) / 2, (1 - y) / 2)
// scaled by uv_scale and shifted by uv_shift.
void add_quad(test::GltfBuilder& b, int material, float x0, float x1, float y0, float y1, float z, bool up = true,
              glm::vec2 uv_scale = {1, 1}, glm::vec2 uv_shift = {0, 0}) {
  std::vector<float> pos = {x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z};
  std::vector<float> uv;
  for (int i = 0; i < 4; ++i) {
    glm::vec2 t((pos[i * 3] + 1) * 0.5f, (1 - pos[i * 3 + 1]) * 0.5f);
    t = t * uv_scale + uv_shift;
    uv.insert(uv.end(), {t.x, t.y});
  }
  const float nz = up ? 1.0f : -1.0f;
  std::vector<float> nrm = {0, 0, nz, 0, 0, nz, 0, 0, nz, 0, 0, nz};
  std::vector<uint16_t> idx = up ? std::vector<uint16_t>{0, 1, 2, 0, 2, 3} : std::vector<uint16_t>{0, 2, 1, 0, 3, 2};
  b.node({{"mesh", b.mesh("quad", pos, nrm, idx, 4, material, uv)}});
}

// A closed box (12 triangles, outward normals, flat) for slabs.
void add_box(test::GltfBuilder& b, int material, glm::vec3 lo, glm::vec3 hi) {
  add_quad(b, material, lo.x, hi.x, lo.y, hi.y, hi.z, true);
  add_quad(b, material, lo.x, hi.x, lo.y, hi.y, lo.z, false);
  auto side = [&](std::vector<float> pos, glm::vec3 n) {
    std::vector<float> nrm;
    for (int i = 0; i < 4; ++i) nrm.insert(nrm.end(), {n.x, n.y, n.z});
    b.node({{"mesh", b.mesh("side", pos, nrm, {0, 1, 2, 0, 2, 3}, 4, material)}});
  };
  side({lo.x, lo.y, lo.z, hi.x, lo.y, lo.z, hi.x, lo.y, hi.z, lo.x, lo.y, hi.z}, {0, -1, 0});
  side({hi.x, hi.y, lo.z, lo.x, hi.y, lo.z, lo.x, hi.y, hi.z, hi.x, hi.y, hi.z}, {0, 1, 0});
  side({lo.x, hi.y, lo.z, lo.x, lo.y, lo.z, lo.x, lo.y, hi.z, lo.x, hi.y, hi.z}, {-1, 0, 0});
  side({hi.x, lo.y, lo.z, hi.x, hi.y, lo.z, hi.x, hi.y, hi.z, hi.x, lo.y, hi.z}, {1, 0, 0});
}

// The rig: camera at z = 5 looking down (+y up in the image) covering [-1, 1]^2, lights.
Scene load_rig(test::GltfBuilder& b, const std::filesystem::path& dir, json lights, json extra = json::object()) {
  b.write(dir);
  json rig = {{"model", "model.gltf"},
              {"camera", {{"eye", {0, 0, 5}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}},
                          {"yfov_deg", 2.0 * std::atan(0.2) * 180.0 / M_PI}}},
              {"lights", lights},
              {"max_depth", 3}};
  for (auto it = extra.begin(); it != extra.end(); ++it) rig[it.key()] = it.value();
  test::write_text(dir / "rig.json", rig.dump());
  return load_scene(dir / "rig.json", LoadOptions{{}, true});
}

json diffuse(glm::vec3 c) {
  return {{"pbrMetallicRoughness", {{"baseColorFactor", {c.r, c.g, c.b, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}};
}
json directional(glm::vec3 to_light, float lux) {
  const glm::vec3 d = -glm::normalize(to_light);
  return {{"type", "directional"}, {"direction", {d.x, d.y, d.z}}, {"intensity", lux}};
}

TEST(GltfMaterials, MetallicRoughnessTextureMirrorsOnlyOnItsMetalHalf) {
  auto dir = test::temp_dir("mr");
  test::GltfBuilder b;
  // 2 x 1: left texel metal and smooth (B = 1, G = 0), right rough dielectric (B = 0, G = 1).
  const int mr = add_texture(b, dir, "mr.png", 2, 1, {0, 0, 255, 255, 0, 255, 0, 255});
  const int floor = add_material(b, {{"pbrMetallicRoughness",
                                      {{"baseColorFactor", {0.8, 0.8, 0.8, 1}},
                                       {"metallicRoughnessTexture", {{"index", mr}}}}}});
  add_quad(b, floor, -1, 1, -1, 1, 0);
  // A red wall above the camera, facing down: only mirrors show it.
  const int wall = add_material(b, {{"emissiveFactor", {1, 0, 0}}, {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}}});
  add_quad(b, wall, -4, 4, -4, 4, 6, false);
  Scene s = load_rig(b, dir, json::array({{{"type", "point"}, {"position", {3, 0, 3}}, {"intensity", 20}}}));
  EXPECT_TRUE(s.effects().material_textures);
  EXPECT_TRUE(s.effects().reflection);
  const Image img = render_scene(s);
  for (float y : {-0.6f, 0.0f, 0.6f}) {
    const glm::vec3 metal = img.at(-0.5f, y), rough = img.at(0.5f, y);
    // Metal: F0 = base 0.8 mirrors the red wall (radiance 1), no diffuse.
    EXPECT_NEAR(metal.r, 0.8f, 0.02f) << y;
    EXPECT_LT(metal.g, 0.01f) << y;
    // Rough dielectric: grey diffuse light, no red reflection.
    EXPECT_GT(rough.g, 0.05f) << y;
    EXPECT_NEAR(rough.r, rough.g, 1e-4f) << y;
  }
}

// Slabs 0.1 thick at z 0.5..0.6 over a white floor, a directional light from (0, 1, 1): the
// fully shadowed floor is y in [-0.7, -0.4]. Glass on the left, opaque on the right.
Scene slab_scene(const std::string& name, json glass_extensions, glm::vec3 tint,
                 json lights = json::array({directional({0, 1, 1}, 3.0f)})) {
  auto dir = test::temp_dir(name);
  test::GltfBuilder b;
  add_quad(b, add_material(b, diffuse(glm::vec3(1.0f))), -1, 1, -1, 1, 0);
  json glass = {{"pbrMetallicRoughness", {{"baseColorFactor", {tint.r, tint.g, tint.b, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
                {"extensions", glass_extensions}};
  add_box(b, add_material(b, glass), {-0.9f, -0.2f, 0.5f}, {-0.1f, 0.2f, 0.6f});
  add_box(b, add_material(b, diffuse(glm::vec3(0.5f))), {0.1f, -0.2f, 0.5f}, {0.9f, 0.2f, 0.6f});
  return load_rig(b, dir, lights);
}

TEST(GltfMaterials, TintedGlassSlabTransmitsATintedShadowAndAnOpaqueSlabABlackOne) {
  const glm::vec3 tint(1.0f, 0.5f, 0.25f);
  Scene s = slab_scene("glass", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}, tint);
  EXPECT_TRUE(s.effects().shadow_transmission);
  const Image img = render_scene(s);
  const glm::vec3 open = img.at(0.0f, -0.55f), glass = img.at(-0.5f, -0.55f), opaque = img.at(0.5f, -0.55f);
  ASSERT_GT(open.r, 0.1f);
  // Two crossings (bottom and top face), each transmission x base colour.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(glass[c] / open[c], tint[c] * tint[c], 0.02f * tint[c] * tint[c] + 1e-4f) << c;
  EXPECT_EQ(opaque, glm::vec3(0.0f));
  // Outside the shadows the floor is the same everywhere along the row.
  EXPECT_NEAR(img.at(-0.5f, -0.9f).r, open.r, 0.02f * open.r);
}

TEST(GltfMaterials, VolumeAttenuatesShadowsByBeersLawOverThePathInside) {
  // Clear glass, attenuation colour 0.5 at distance 0.1: the path inside is 0.1 / cos 45.
  Scene s = slab_scene("volume",
                       {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                        {"KHR_materials_volume",
                         {{"thicknessFactor", 0.1}, {"attenuationColor", {0.5, 0.5, 0.5}}, {"attenuationDistance", 0.1}}}},
                       glm::vec3(1.0f));
  EXPECT_TRUE(s.effects().absorption);
  const Image img = render_scene(s);
  const float expected = std::pow(0.5f, std::sqrt(2.0f));
  EXPECT_NEAR(img.at(-0.5f, -0.55f).g / img.at(0.0f, -0.55f).g, expected, 0.01f);
}

// The same through a point light's shadow ray, whose direction is not a unit vector (it
// spans the way to the light): the path inside is the hit distance in units of its length
// (mutation testing: dropping the length failed only a golden image). Against the same slab
// without a volume (thin-walled, both faces passing all), so only Beer's factor remains.
TEST(GltfMaterials, VolumeAttenuatesAPointLightsShadowOverThePathInside) {
  const glm::vec3 light(-0.5f, 2.5f, 3.0f);
  const json point = json::array({{{"type", "point"}, {"position", {light.x, light.y, light.z}}, {"intensity", 20.0}}});
  const json clear = {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}};
  json absorbing = clear;
  absorbing["KHR_materials_volume"] = {{"thicknessFactor", 0.1}, {"attenuationColor", {0.5, 0.5, 0.5}}, {"attenuationDistance", 0.1}};
  const Image with_volume = render_scene(slab_scene("pointvolume", absorbing, glm::vec3(1.0f), point));
  const Image thin = render_scene(slab_scene("pointthin", clear, glm::vec3(1.0f), point));
  // The floor point (-0.5, -0.55) sees the light through the slab (z 0.5..0.6) at y ~ 0;
  // the camera sees the point directly.
  const glm::vec3 floor_point((float(px(-0.5f)) + 0.5f) / kSize * 2.0f - 1.0f, 1.0f - (float(py(-0.55f)) + 0.5f) / kSize * 2.0f, 0.0f);
  const glm::vec3 to_light = light - floor_point;
  const float inside = 0.1f * glm::length(to_light) / to_light.z;
  const float open = thin.at(-0.5f, -0.55f).g;
  ASSERT_GT(open, 0.05f);
  EXPECT_NEAR(with_volume.at(-0.5f, -0.55f).g / open, std::pow(0.5f, inside / 0.1f), 0.01f);
}

// A quad at z = 0.5 over y in [0, 0.4], half cut out by its texture's alpha, over a floor lit
// from (0, 1, 1): the shadow falls on y in [-0.5, -0.1].
Scene masked_scene(const std::string& name, json material_extra, bool quad = true) {
  auto dir = test::temp_dir(name);
  test::GltfBuilder b;
  add_quad(b, add_material(b, diffuse(glm::vec3(1.0f))), -1, 1, -1, 1, 0);
  if (quad) {
    // 2 x 1: left texel alpha 0, right alpha 1.
    const int tex = add_texture(b, dir, "alpha.png", 2, 1, {255, 255, 255, 0, 255, 255, 255, 255});
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.1, 0.9, 0.1, 1}}, {"metallicFactor", 0},
                                        {"baseColorTexture", {{"index", tex}}}}}};
    for (auto it = material_extra.begin(); it != material_extra.end(); ++it) m[it.key()] = it.value();
    add_quad(b, add_material(b, m), -0.8f, 0.8f, 0.0f, 0.4f, 0.5f);
  }
  return load_rig(b, dir, json::array({directional({0, 1, 1}, 3.0f)}));
}

TEST(GltfMaterials, AlphaMaskedQuadCastsAShadowWithTheMasksShape) {
  Scene s = masked_scene("mask", {{"alphaMode", "MASK"}});
  EXPECT_TRUE(s.effects().alpha_mask);
  const Image img = render_scene(s);
  const glm::vec3 open = img.at(0.0f, -0.8f);
  ASSERT_GT(open.r, 0.1f);
  // The solid right half shadows, the cut-out left half does not.
  EXPECT_EQ(img.at(0.4f, -0.3f), glm::vec3(0.0f));
  EXPECT_NEAR(img.at(-0.4f, -0.3f).r, open.r, 0.02f * open.r);
  // The camera sees the floor through the cut-out (white), the quad where solid (green).
  const glm::vec3 through = img.at(-0.4f, 0.2f), solid = img.at(0.4f, 0.2f);
  EXPECT_NEAR(through.r, through.g, 1e-4f);
  EXPECT_GT(solid.g, 5.0f * solid.r);
  // Without MASK the texture's alpha is ignored: the whole quad shadows.
  Scene opaque = masked_scene("opaque", json::object());
  EXPECT_FALSE(opaque.effects().alpha_mask);
  EXPECT_EQ(render_scene(opaque).at(-0.4f, -0.3f), glm::vec3(0.0f));
}

TEST(GltfMaterials, AlphaBlendMixesTheSurfaceOverWhatIsBehindIt) {
  // Uniform alpha 0.25 (factor; the texture's right texel has alpha 1).
  json blend = {{"alphaMode", "BLEND"}};
  Scene s = masked_scene("blend", blend);
  s.materials[1].base_color_texture = TextureRef{};  // uniform alpha = the factor
  s.materials[1].base_alpha = 0.25f;
  s.finalize_materials();
  EXPECT_TRUE(s.effects().alpha_blend);
  Scene solid = s;
  solid.materials[1].alpha_mode = AlphaMode::Opaque;
  solid.finalize_materials();
  const Scene bare = masked_scene("bare", json::object(), false);
  const Image mixed = render_scene(s), front = render_scene(solid), behind = render_scene(bare);
  for (glm::vec2 p : {glm::vec2(0.4f, 0.2f), glm::vec2(-0.4f, 0.2f), glm::vec2(0.4f, -0.3f)}) {
    const glm::vec3 expected = 0.25f * front.at(p.x, p.y) + 0.75f * behind.at(p.x, p.y);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mixed.at(p.x, p.y)[c], expected[c], 1e-3f * expected[c] + 1e-5f) << p.x << p.y;
  }
  // The shadow passes 1 - alpha of the light.
  EXPECT_NEAR(mixed.at(0.4f, -0.3f).r / behind.at(0.4f, -0.3f).r, 0.75f, 0.01f);
}

// Radiance of a diffuse white (roughness 1) floor point seen from straight above under a
// directional light: Lambert + the normalised Phong lobe with n = 1, F0 = 0.04.
float lit_radiance(glm::vec3 n, glm::vec3 wi, glm::vec3 wo, float lux) {
  const float cos_s = std::max(0.0f, glm::dot(n, wi));
  const glm::vec3 r = 2.0f * glm::dot(n, wi) * n - wi;
  return lux * cos_s * (1.0f / kPi + 0.04f * 3.0f / (2.0f * kPi) * std::max(0.0f, glm::dot(r, wo)));
}

TEST(GltfMaterials, NormalMappedPlaneShadesAsTheMappedNormalSays) {
  // 2 x 1 normal map: left tilted towards +u (tangent, world +x), right towards image-up
  // (+Y, world +y since v grows down the image). Tangents generated from the UVs.
  const glm::vec3 tilt_x = glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f)), tilt_y = glm::normalize(glm::vec3(0.0f, 0.5f, 1.0f));
  auto q = [](float c) { return uint8_t(std::lround((c * 0.5f + 0.5f) * 255.0f)); };
  auto decoded = [](glm::vec3 n) {
    glm::vec3 t;
    for (int c = 0; c < 3; ++c) t[c] = std::lround((n[c] * 0.5f + 0.5f) * 255.0f) / 255.0f * 2.0f - 1.0f;
    return glm::normalize(t);
  };
  for (glm::vec3 to_light : {glm::vec3(1, 0, 1), glm::vec3(0, 1, 1)}) {
    auto dir = test::temp_dir(to_light.x > 0 ? "nx" : "ny");
    test::GltfBuilder b;
    const int nt = add_texture(b, dir, "n.png", 2, 1,
                               {q(tilt_x.x), q(tilt_x.y), q(tilt_x.z), 255, q(tilt_y.x), q(tilt_y.y), q(tilt_y.z), 255});
    json m = diffuse(glm::vec3(1.0f));
    m["normalTexture"] = {{"index", nt}};
    add_quad(b, add_material(b, m), -1, 1, -1, 1, 0);
    Scene s = load_rig(b, dir, json::array({directional(to_light, 2.0f)}));
    EXPECT_TRUE(s.effects().normal_maps);
    const Image img = render_scene(s);
    const glm::vec3 wi = glm::normalize(to_light);
    for (float x : {-0.5f, 0.5f}) {
      const float y = 0.02f;
      const glm::vec3 p((px(x) + 0.5f) / 32.0f - 1.0f, 1.0f - (py(y) + 0.5f) / 32.0f, 0.0f);
      const glm::vec3 wo = glm::normalize(glm::vec3(0, 0, 5) - p);
      const glm::vec3 n = decoded(x < 0 ? tilt_x : tilt_y);
      const float expected = lit_radiance(n, wi, wo, 2.0f);
      EXPECT_NEAR(img.at(x, y).r, expected, 2e-3f * expected) << to_light.x << " " << x;
      // And it differs from the unmapped plane's radiance.
      EXPECT_GT(std::abs(expected - lit_radiance({0, 0, 1}, wi, wo, 2.0f)), 0.02f * expected);
    }
  }
}

// Emissive-only floor (no lights) whose emissive texture is 2 x 1 black | white.
Scene emissive_floor(const std::string& name, json texture_info, json sampler, glm::vec2 uv_scale = {1, 1},
                     glm::vec2 uv_shift = {0, 0}) {
  auto dir = test::temp_dir(name);
  test::GltfBuilder b;
  const int tex = add_texture(b, dir, "bw.png", 2, 1, {0, 0, 0, 255, 255, 255, 255, 255}, sampler);
  texture_info["index"] = tex;
  const int m = add_material(b, {{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", texture_info},
                                 {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}}});
  add_quad(b, m, -1, 1, -1, 1, 0, true, uv_scale, uv_shift);
  return load_rig(b, dir, json::array());
}

// u of the first black-to-white step along the middle row, from u(x) = x_to_u(x).
float first_rise(const Image& img, float u0, float u1) {
  for (int x = 1; x < kSize; ++x) {
    const float a = img.film.radiance[size_t(kSize / 2) * kSize + size_t(x - 1)].r;
    const float c = img.film.radiance[size_t(kSize / 2) * kSize + size_t(x)].r;
    if (a < 0.5f && c > 0.5f) return u0 + (u1 - u0) * float(x) / kSize;
  }
  return NAN;
}

TEST(GltfMaterials, TextureTransformShiftsThePatternByItsOffset) {
  const json nearest = {{"magFilter", 9728}, {"minFilter", 9728}};
  const Image plain = render_scene(emissive_floor("plain", json::object(), nearest));
  const Image shifted = render_scene(emissive_floor(
      "shifted", {{"extensions", {{"KHR_texture_transform", {{"offset", {0.25, 0.0}}}}}}}, nearest));
  // Black | white switches at u = 0.5 (x = 0); offset 0.25 moves it to u = 0.25 (x = -0.5).
  EXPECT_NEAR(first_rise(plain, 0.0f, 1.0f), 0.5f, 1.0f / kSize);
  EXPECT_NEAR(first_rise(shifted, 0.0f, 1.0f), 0.25f, 1.0f / kSize);
  // Either side of the shifted step.
  EXPECT_EQ(shifted.at(-0.75f, 0.0f), glm::vec3(0.0f));
  EXPECT_EQ(shifted.at(-0.25f, 0.0f), glm::vec3(1.0f));
}

// KHR_texture_transform's texCoord overrides the texture's own set (review: no test set it,
// so dropping the override passed). TEXCOORD_1 runs the other way along x from TEXCOORD_0.
TEST(GltfMaterials, TextureTransformsTexCoordPicksTheUvSet) {
  const json nearest = {{"magFilter", 9728}, {"minFilter", 9728}};
  auto render = [&](const std::string& name, json texture_info) {
    auto dir = test::temp_dir(name);
    test::GltfBuilder b;
    texture_info["index"] = add_texture(b, dir, "bw.png", 2, 1, {0, 0, 0, 255, 255, 255, 255, 255}, nearest);
    const int m = add_material(b, {{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", texture_info},
                                   {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}}});
    add_quad(b, m, -1, 1, -1, 1, 0);
    b.doc["meshes"].back()["primitives"][0]["attributes"]["TEXCOORD_1"] = b.floats({1, 1, 0, 1, 0, 0, 1, 0}, 2);
    return render_scene(load_rig(b, dir, json::array()));
  };
  const Image set0 = render("set0", {{"texCoord", 1}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 0}}}}}});
  const Image set1 = render("set1", {{"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}});
  const Image own = render("own", {{"texCoord", 1}});
  for (const Image* img : {&set1, &own}) {  // u1 = 1 - u0: white on the left, black on the right
    EXPECT_EQ(img->at(-0.5f, 0.0f), glm::vec3(1.0f));
    EXPECT_EQ(img->at(0.5f, 0.0f), glm::vec3(0.0f));
  }
  EXPECT_EQ(set0.at(-0.5f, 0.0f), glm::vec3(0.0f));
  EXPECT_EQ(set0.at(0.5f, 0.0f), glm::vec3(1.0f));
}

TEST(GltfMaterials, WrapModesBeyondTheUnitSquare) {
  // u runs from -1 to 2 across the frame; texel 0 black, texel 1 white.
  auto render = [&](int wrap) {
    json sampler = {{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", wrap}};
    return render_scene(emissive_floor("wrap" + std::to_string(wrap), json::object(), sampler, {3, 1}, {-1, 0}));
  };
  auto at_u = [](const Image& img, float u) { return img.at((u + 1.0f) / 3.0f * 2.0f - 1.0f, 0.0f).r; };
  const Image repeat = render(10497), clamp = render(33071), mirror = render(33648);
  const float us[] = {-0.75f, -0.25f, 0.25f, 0.75f, 1.25f, 1.75f};
  const float want_repeat[] = {0, 1, 0, 1, 0, 1}, want_clamp[] = {0, 0, 0, 1, 1, 1}, want_mirror[] = {1, 0, 0, 1, 1, 0};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(at_u(repeat, us[i]), want_repeat[i]) << us[i];
    EXPECT_EQ(at_u(clamp, us[i]), want_clamp[i]) << us[i];
    EXPECT_EQ(at_u(mirror, us[i]), want_mirror[i]) << us[i];
  }
}

TEST(GltfMaterials, BareGltfWithoutLightsGetsTheDefaultLightsAndAWarning) {
  auto dir = test::temp_dir("bare");
  test::GltfBuilder b;
  add_quad(b, add_material(b, diffuse(glm::vec3(0.8f))), -1, 1, -1, 1, 0);
  const auto file = b.write(dir);
  testing::internal::CaptureStderr();
  Scene s = load_scene(file);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("no lights in the file; using a default headlight and key light"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  ASSERT_EQ(s.lights.size(), 2u);
  // The auto camera sees the quad lit (not black) by the defaults.
  const Image img = render_scene(s);
  EXPECT_GT(img.film.radiance[size_t(kSize / 2) * kSize + kSize / 2].r, 0.1f);
}

TEST(GltfMaterials, SceneWithoutTrianglesIsAnError) {
  auto dir = test::temp_dir("empty");
  test::GltfBuilder b;
  b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
  b.node({{"camera", 0}});
  b.node({{"mesh", b.mesh("lines", test::kTriPos, {}, {}, 1)}});  // lines only: skipped
  const auto file = b.write(dir);
  try {
    load_scene(file, LoadOptions{{}, true});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
  }
}

TEST(GltfMaterials, CameraByNameAndFrameAspect) {
  auto dir = test::temp_dir("cams");
  test::GltfBuilder b;
  add_quad(b, add_material(b, diffuse(glm::vec3(0.8f))), -1, 1, -1, 1, 0);
  b.doc["cameras"] = {{{"name", "wide"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"aspectRatio", 1.5}}}},
                      {{"name", "tall"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}, {"aspectRatio", 0.5}}}}};
  b.node({{"camera", 0}, {"translation", {0, 0, 5}}});
  b.node({{"camera", 1}, {"translation", {0, 0, 4}}});
  Scene s = load_scene(b.write(dir), LoadOptions{{}, true});
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(find_camera(s, "tall"), 1u);
  EXPECT_EQ(find_camera(s, "1"), 1u);
  EXPECT_EQ(find_camera(s, "wide"), 0u);
  EXPECT_THROW(find_camera(s, "nope"), Error);
  EXPECT_THROW(find_camera(s, "2"), Error);
  // Default 512 on the longer side, the other from the camera's aspect.
  EXPECT_EQ(frame_size(s, s.cameras[0]).width, 512);
  EXPECT_EQ(frame_size(s, s.cameras[0]).height, 341);
  EXPECT_EQ(frame_size(s, s.cameras[1]).width, 256);
  EXPECT_EQ(frame_size(s, s.cameras[1]).height, 512);
  // A side from the command line or the rig wins; the other follows the aspect.
  EXPECT_EQ(frame_size(s, s.cameras[0], 300).height, 200);
  EXPECT_EQ(frame_size(s, s.cameras[0], 0, 100).width, 150);
  s.width_given = s.height_given = true;
  EXPECT_EQ(frame_size(s, s.cameras[0]).width, 512);
  EXPECT_EQ(frame_size(s, s.cameras[0]).height, 512);
}

TEST(SharedScenes, RenderWithoutNanOrInf) {
  const auto root = test::shared_scenes();
  if (!std::filesystem::exists(root / "toycar"))
    GTEST_SKIP() << "shared third-party scenes not found at " << root << " (optional)";
  LoadOptions opt{root, true};
  for (const char* file : {"car.json", "vase.json", "lamp.json"}) {
    const Scene s = load_scene(std::filesystem::path(ZZ_SOURCE_DIR) / "scenes" / file, opt);
    const Bvh bvh = Bvh::build(s.positions);
    const Shader shader(s, bvh);
    RenderSettings rs;
    rs.width = rs.height = 48;
    rs.aa = AaMode::None;
    Film film;
    RenderStats stats;
    render_frame(shader, s.cameras[0], GeoMap{}, rs, film, stats);
    double sum = 0.0;
    for (const glm::vec3& c : film.radiance) {
      ASSERT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) << file;
      ASSERT_TRUE(c.r >= 0.0f && c.g >= 0.0f && c.b >= 0.0f) << file;
      sum += c.r + c.g + c.b;
    }
    EXPECT_GT(sum, 0.0) << file;
    EXPECT_EQ(stats.rays.nan_radiance, 0u) << file;
    EXPECT_EQ(stats.rays.capped_radiance, 0u) << file;  // +Inf, which the film cannot show
  }
}

}  // namespace
}  // namespace zz
