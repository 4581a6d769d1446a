// The AOV names and the raw channels each adds to a multi-layer EXR.
#include "render/aov_layers.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/error.h"

namespace zz {
namespace {

TEST(AovLayers, NamesAndChannelsAreTheDocumentedOnes) {
  EXPECT_EQ(aov_names(), "rays, level, geo, depth, normal, albedo");
  std::vector<std::string> all;
  for (Aov a : kAllAovs) {
    EXPECT_EQ(find_aov(aov_name(a)), a);
    for (const std::string& c : aov_channel_names(a)) all.push_back(c);
  }
  EXPECT_EQ(all, (std::vector<std::string>{"rays", "level", "geo", "depth", "normal.X", "normal.Y", "normal.Z",
                                           "albedo.R", "albedo.G", "albedo.B"}));
  EXPECT_EQ(find_aov("levels"), Aov::Level);  // the heatmap's older name still works
  EXPECT_FALSE(find_aov("Rays").has_value());
  EXPECT_FALSE(find_aov("z").has_value());
}

TEST(AovLayers, ChannelsHoldTheFilmsRawValues) {
  Film film(3, 2);
  film.rays = {1, 9, 25, 255, 5, 1};
  film.level = {1, 2, 3, 1 + 4, 2 + 4, 3 + 4};  // +4 = vertical: not part of the level channel
  GeoMap geo{3, 2, {0, 1, 0, 0, 7, 0}};
  PrimaryHits hits;
  hits.width = 3;
  hits.height = 2;
  const float inf = std::numeric_limits<float>::infinity();
  hits.depth = {1.5f, 2.0f, inf, 3.0f, 4.0f, 5.0f};
  hits.normal.assign(6, glm::vec3(0, 0, 1));
  hits.normal[2] = glm::vec3(0.0f);
  hits.albedo.assign(6, glm::vec3(0.1f, 0.2f, 0.3f));
  // Asked in another order and twice: channels come once each, in the documented order.
  const std::vector<FilmChannel> c =
      aov_channels({Aov::Albedo, Aov::Depth, Aov::Rays, Aov::Geo, Aov::Level, Aov::Normal, Aov::Rays}, film, geo, hits);
  ASSERT_EQ(c.size(), 10u);
  EXPECT_EQ(c[0].name, "rays");
  EXPECT_EQ(c[0].values, (std::vector<float>{1, 9, 25, 255, 5, 1}));
  EXPECT_EQ(c[1].name, "level");
  EXPECT_EQ(c[1].values, (std::vector<float>{1, 2, 3, 1, 2, 3}));
  EXPECT_EQ(c[2].name, "geo");
  EXPECT_EQ(c[2].values, (std::vector<float>{0, 1, 0, 0, 1, 0}));
  EXPECT_EQ(c[3].name, "depth");
  EXPECT_EQ(c[3].values, hits.depth);
  EXPECT_EQ(c[6].name, "normal.Z");
  EXPECT_EQ(c[6].values, (std::vector<float>{1, 1, 0, 1, 1, 1}));
  EXPECT_EQ(c[8].name, "albedo.G");
  EXPECT_EQ(c[8].values, std::vector<float>(6, 0.2f));
}

TEST(AovLayers, GeoWithoutAMapIsAnError) {
  Film film(2, 2);
  EXPECT_THROW(aov_channels({Aov::Geo}, film, GeoMap{}, PrimaryHits{}), Error);
  EXPECT_THROW(aov_channels({Aov::Depth}, film, GeoMap{}, PrimaryHits{}), Error);
  EXPECT_EQ(aov_channels({Aov::Rays}, film, GeoMap{}, PrimaryHits{}).size(), 1u);
}

}  // namespace
}  // namespace zz
