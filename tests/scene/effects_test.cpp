#include <gtest/gtest.h>

#include "scene/loader.h"
#include "scene/scene.h"

namespace zz {
namespace {

using Names = std::vector<std::string>;

// One triangle per material in `used`; all of `mats` are in the scene.
Scene scene_with(std::vector<Material> mats, std::vector<uint32_t> used, size_t lights = 0) {
  Scene s;
  s.materials = std::move(mats);
  for (uint32_t m : used) {
    s.positions.insert(s.positions.end(), {glm::vec3(0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)});
    s.normals.insert(s.normals.end(), 3, glm::vec3(0, 0, 1));
    s.uvs.insert(s.uvs.end(), 3, glm::vec2(0));
    s.material_of.push_back(m);
  }
  s.lights.resize(lights);
  s.finalize_materials();
  return s;
}

Material mirror() {
  Material m;
  m.metallic = 1.0f;
  m.roughness = 0.0f;
  return m;
}
Material glass(bool tinted) {
  Material m;
  m.transmission = 1.0f;
  m.roughness = 0.0f;
  if (tinted) m.thickness = 1.0f, m.attenuation_distance = 1.0f, m.attenuation_color = glm::vec3(0.5f);
  return m;
}

TEST(EffectSet, NamesInFixedOrder) {
  EffectSet all{true, true, true, true, true, true};
  EXPECT_EQ(all.names(), (Names{"shadows", "reflection", "refraction", "absorption", "textures", "emission"}));
  EXPECT_TRUE(EffectSet{}.names().empty());
}

TEST(EffectSet, FollowsLightsAndUsedMaterials) {
  Material rough;  // default: diffuse only
  EXPECT_TRUE(scene_with({rough}, {0}).effects().names().empty());
  EXPECT_EQ(scene_with({rough}, {0}, 2).effects().names(), Names{"shadows"});
  EXPECT_EQ(scene_with({rough, mirror()}, {0, 1}).effects().names(), Names{"reflection"});
  // A material no triangle uses switches nothing on.
  EXPECT_TRUE(scene_with({rough, mirror(), glass(true)}, {0}).effects().names().empty());
  EXPECT_EQ(scene_with({glass(false)}, {0}).effects().names(), (Names{"reflection", "refraction"}));
  EXPECT_EQ(scene_with({glass(true)}, {0}).effects().names(), (Names{"reflection", "refraction", "absorption"}));
  Material lamp;
  lamp.emissive = glm::vec3(2.0f);
  EXPECT_EQ(scene_with({lamp}, {0}).effects().names(), Names{"emission"});
  Material textured;
  textured.base_color_texture.index = 0;
  Scene t = scene_with({textured}, {0});
  EXPECT_TRUE(t.effects().names().empty());  // index without a texture behind it
  Texture white;
  white.width = white.height = 1;
  white.texels = {glm::vec4(1)};
  t.textures.push_back(white);
  EXPECT_EQ(t.effects().names(), Names{"textures"});
}

TEST(EffectSet, ProjectScenes) {
  const std::pair<const char*, Names> cases[] = {
      {"room.json", {"shadows", "reflection"}},
      {"glass.json", {"shadows", "reflection", "refraction", "absorption", "shadow_transmission"}},
      {"default.json", {"shadows", "reflection", "refraction", "shadow_transmission"}}};
  for (const auto& [file, names] : cases)
    EXPECT_EQ(load_scene(std::filesystem::path(ZZ_SOURCE_DIR) / "scenes" / file, LoadOptions{{}, true}).effects().names(),
              names)
        << file;
}

}  // namespace
}  // namespace zz
