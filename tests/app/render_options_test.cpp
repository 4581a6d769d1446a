// The command line parsed into typed options: one set of defaults, names mapped to enums,
// bad values and combinations rejected before anything is loaded (issue 13).
#include "app/batch_options.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace zz {
namespace {

// Parses `zigzag render ARGS` into o; returns CLI11's or validate()'s error text, "" if fine.
std::string parse(std::vector<std::string> args, BatchOptions& o) {
  CLI::App app;
  CLI::App* cmd = app.add_subcommand("render");
  add_batch_options(cmd, o);
  args.insert(args.begin(), "render");
  std::reverse(args.begin(), args.end());  // CLI11 takes a vector in reverse order
  try {
    app.parse(args);
    validate(o);
  } catch (const CLI::ParseError& e) {
    return std::string("cli: ") + e.what();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(RenderOptions, DefaultsAreTheDocumentedOnes) {
  BatchOptions o;
  ASSERT_EQ(parse({"a.json"}, o), "");
  EXPECT_EQ(o.render.aa, AaMode::Adaptive);
  EXPECT_FLOAT_EQ(o.render.adaptive.eps, 0.05f);
  EXPECT_STREQ(o.render.adaptive.tables->name, "tuned");
  EXPECT_EQ(o.render.adaptive.geo_policy, GeoPolicy::Split);
  EXPECT_EQ(o.render.adaptive.filter, Filter::Box);
  EXPECT_EQ(o.render.adaptive.signature, unsigned(kSignatureAll));
  EXPECT_TRUE(o.render.adaptive.highlights);
  EXPECT_FALSE(o.render.adaptive.textures);
  EXPECT_TRUE(o.render.adaptive.curvature);
  EXPECT_TRUE(o.render.adaptive.hdr_zones);
  EXPECT_TRUE(o.render.adaptive.footprint);
  EXPECT_TRUE(o.render.adaptive.geo_orient);
  EXPECT_TRUE(o.render.adaptive.geo_zones);
  EXPECT_TRUE(o.render.adaptive.split_unflagged);
  EXPECT_TRUE(o.render.adaptive.fill_gaps);
  EXPECT_FLOAT_EQ(o.render.adaptive.eps_specular, 0.01f);
  EXPECT_EQ(o.render.edges, EdgeMode::Vulkan);
  EXPECT_EQ(o.render.pattern, UniformPattern::Stratified);
  EXPECT_EQ(o.output_pattern(), "{scene}.png");
}

TEST(RenderOptions, NamesBecomeEnums) {
  BatchOptions o;
  ASSERT_EQ(parse({"a.json", "--aa", "uniform", "--pattern", "grid", "--spp", "16", "--tables", "paper",
                   "--geo-policy", "paper", "--filter", "mitchell", "--edges", "off"},
                  o),
            "");
  EXPECT_EQ(o.render.aa, AaMode::Uniform);
  EXPECT_EQ(o.render.pattern, UniformPattern::Grid);
  EXPECT_STREQ(o.render.adaptive.tables->name, "paper");
  EXPECT_EQ(o.render.adaptive.geo_policy, GeoPolicy::Paper);
  EXPECT_EQ(o.render.adaptive.filter, Filter::Mitchell);
  EXPECT_EQ(o.render.edges, EdgeMode::Off);
  EXPECT_STREQ(name_of(kFilters, o.render.adaptive.filter), "mitchell");
}

TEST(RenderOptions, DetailFlagsAndCurvatureReachTheSamplerSettings) {
  BatchOptions o;
  ASSERT_EQ(parse({"a.json", "--highlights", "on", "--textures", "on", "--curvature", "on", "--signature", "lights",
                   "--hdr-zones", "on", "--footprint", "on", "--geo-orient", "on", "--geo-zones", "on",
                   "--split-unflagged", "on", "--fill-gaps", "on"},
                  o),
            "");
  AdaptiveSettings s;
  apply_adaptive_options(o.render.adaptive, s);
  EXPECT_TRUE(s.highlights);
  EXPECT_TRUE(s.textures);
  EXPECT_TRUE(s.curvature);
  EXPECT_TRUE(s.hdr_zones);
  EXPECT_TRUE(s.footprint);
  EXPECT_TRUE(s.geo_orient);
  EXPECT_TRUE(s.geo_zones);
  EXPECT_TRUE(s.split_unflagged);
  EXPECT_TRUE(s.fill_gaps);
  EXPECT_EQ(s.signature, unsigned(kSignatureLights));
  EXPECT_FLOAT_EQ(s.eps, 0.05f);
  BatchOptions off;
  ASSERT_EQ(parse({"a.json", "--highlights", "off", "--textures", "off", "--curvature", "off", "--hdr-zones", "off",
                   "--footprint", "off", "--geo-orient", "off",
                   "--geo-zones", "off", "--split-unflagged", "off", "--fill-gaps", "off"},
                  off),
            "");
  apply_adaptive_options(off.render.adaptive, s);
  EXPECT_FALSE(s.highlights || s.textures || s.curvature || s.hdr_zones || s.footprint || s.geo_orient || s.geo_zones ||
               s.split_unflagged || s.fill_gaps);
}

TEST(RenderOptions, TheMirrorsThresholdIsANumberOrOff) {
  BatchOptions o;
  ASSERT_EQ(parse({"a.json", "--eps-specular", "0.02"}, o), "");
  AdaptiveSettings s;
  apply_adaptive_options(o.render.adaptive, s);
  EXPECT_FLOAT_EQ(s.eps_specular, 0.02f);
  BatchOptions off;
  ASSERT_EQ(parse({"a.json", "--eps-specular", "off"}, off), "");
  apply_adaptive_options(off.render.adaptive, s);
  EXPECT_LT(s.eps_specular, 0.0f);
  for (const char* bad : {"2", "-0.1", "abc", "0.01x", ""}) {
    BatchOptions b;
    EXPECT_NE(parse({"a.json", "--eps-specular", bad}, b), "") << bad;
  }
}

TEST(RenderOptions, TheMaterialRuleReachesTheVisibilitySettings) {
  BatchOptions o;
  ASSERT_EQ(parse({"a.json"}, o), "");
  EXPECT_TRUE(make_visibility_settings(o.render).material_edges);
  for (const char* v : {"on", "off"}) {
    BatchOptions p;
    ASSERT_EQ(parse({"a.json", "--edge-material", v}, p), "");
    EXPECT_EQ(make_visibility_settings(p.render).material_edges, std::string(v) == "on");
  }
}

// The highlight flag leaves normal steps wider than the map's angle to the map, and only
// when a map is made.
TEST(RenderOptions, TheMapsAngleReachesTheHighlightFlag) {
  BatchOptions o;
  ASSERT_EQ(parse({"a.json"}, o), "");
  EXPECT_NEAR(map_crease(o.render), 2.0f * std::sin(12.5f * 3.14159265f / 180.0f), 1e-6f);
  BatchOptions wide;
  ASSERT_EQ(parse({"a.json", "--edge-angle", "60"}, wide), "");
  EXPECT_NEAR(map_crease(wide.render), 1.0f, 1e-6f);
  BatchOptions off;
  ASSERT_EQ(parse({"a.json", "--edges", "off"}, off), "");
  EXPECT_EQ(map_crease(off.render), 0.0f);
}

TEST(RenderOptions, BadValuesAreRejectedWhileParsing) {
  for (std::vector<std::string> bad : std::vector<std::vector<std::string>>{
           {"--tables", "nope"}, {"--geo-policy", "x"}, {"--filter", "gauss"}, {"--aa", "magic"},
           {"--pattern", "zigzag"}, {"--edges", "on"}, {"--max-depth", "17"}, {"--max-depth", "-1"},
           {"--highlights", "yes"}, {"--textures", "1"}, {"--curvature", "maybe"}, {"--footprint", "2"}, {"--edge-material", "yes"},
           {"--hdr-zones", "1"},
           // NaN passes CLI11's own range checks (both comparisons false): each number option refuses it.
           {"--eps", "nan"}, {"--exposure", "nan"}, {"--edge-angle", "nan"}, {"--edge-depth", "nan"}, {"--time", "nan"},
           {"--fps", "nan"}, {"--eps", "inf"}, {"--exposure", "-inf"}, {"--eps", "0.1x"},
           {"--output", ""}, {"--stats", ""}}) {
    BatchOptions o;
    bad.insert(bad.begin(), "a.json");
    const std::string e = parse(bad, o);
    EXPECT_EQ(e.rfind("cli: ", 0), 0u) << bad[1] << " " << bad[2] << " -> " << e;
    EXPECT_NE(e.find(bad[1]), std::string::npos) << e;
  }
}

TEST(RenderOptions, CombinationsAreCheckedBeforeLoading) {
  BatchOptions a, b, c, d;
  EXPECT_NE(parse({"a.json", "--aa", "uniform", "--spp", "7"}, a).find("perfect square"), std::string::npos);
  EXPECT_NE(parse({"a.json", "--aa", "uniform", "--pattern", "lattice", "--spp", "16"}, b).find("lattice"),
            std::string::npos);
  EXPECT_NE(parse({"a.json", "b.json", "-o", "x.png"}, c).find("add {scene}"), std::string::npos);
  EXPECT_NE(parse({"a.json", "--camera", "all", "-o", "{scene}.png"}, d).find("add {camera}"), std::string::npos);
}

// README: the default output is {scene}.png, {scene}_{camera}.png with --camera all (so
// `--camera all` alone is a batch whose cameras do not collide).
TEST(RenderOptions, TheDefaultOutputNamesTheCameraUnderCameraAll) {
  BatchOptions all;
  EXPECT_EQ(parse({"a.json", "--camera", "all"}, all), "");
  EXPECT_EQ(all.output_pattern(), "{scene}_{camera}.png");
  BatchOptions named;
  EXPECT_EQ(parse({"a.json", "--camera", "front"}, named), "");
  EXPECT_EQ(named.output_pattern(), "{scene}.png");
}

// --aov geo is the visibility map, which --edges off never makes: refused before loading.
TEST(RenderOptions, TheGeoAovNeedsTheVisibilityMap) {
  BatchOptions off;
  EXPECT_NE(parse({"a.json", "--edges", "off", "--aov", "geo", "g.png"}, off).find("--aov geo needs the visibility map"),
            std::string::npos);
  BatchOptions on;
  EXPECT_EQ(parse({"a.json", "--aov", "geo", "g.png"}, on), "");
}

// README: every option is checked before the first scene is loaded; an empty --region
// (X0 >= X1 or Y0 >= Y1) needs no scene to be wrong, so validate() refuses it.
TEST(RenderOptions, AnEmptyRegionIsRefusedBeforeLoading) {
  for (const char* region : {"5,5,5,10", "10,0,5,10", "0,7,10,7"}) {
    BatchOptions o;
    EXPECT_NE(parse({"a.json", "--region", region}, o).find("the region is empty"), std::string::npos) << region;
  }
  BatchOptions fine;
  EXPECT_EQ(parse({"a.json", "--region", "0,0,1,1"}, fine), "");
}

// The options a batch's mode never reads, as given on the command line.
std::vector<std::string> inapplicable(std::vector<std::string> args) {
  BatchOptions o;
  CLI::App app;
  CLI::App* cmd = app.add_subcommand("render");
  add_batch_options(cmd, o);
  args.insert(args.begin(), "render");
  std::reverse(args.begin(), args.end());
  app.parse(args);
  return inapplicable_options(*cmd, o);
}

TEST(RenderOptions, OptionsTheModeNeverReadsAreNamed) {
  EXPECT_TRUE(inapplicable({"a.json"}).empty());
  EXPECT_TRUE(inapplicable({"a.json", "--eps", "0.1", "--filter", "mitchell", "--edge-ss", "6"}).empty());
  EXPECT_TRUE(inapplicable({"a.json", "--aa", "uniform", "--spp", "16", "--pattern", "grid"}).empty());
  // Defaults are not "given": only what the command line says counts.
  const auto uniform = inapplicable({"a.json", "--aa", "uniform", "--filter", "mitchell", "--edge-ss", "6"});
  ASSERT_EQ(uniform.size(), 2u);
  EXPECT_EQ(uniform[0], "--filter applies to --aa adaptive only, not --aa uniform: ignored");
  EXPECT_NE(uniform[1].find("--edge-ss needs the visibility map"), std::string::npos) << uniform[1];
  const auto adaptive = inapplicable({"a.json", "--spp", "16"});
  ASSERT_EQ(adaptive.size(), 1u);
  EXPECT_EQ(adaptive[0], "--spp applies to --aa uniform only, not --aa adaptive: ignored");
  const auto none = inapplicable({"a.json", "--aa", "none", "--eps", "0.1", "--eps-specular", "off"});
  EXPECT_EQ(none.size(), 2u);
  const auto no_map = inapplicable({"a.json", "--edges", "off", "--edge-angle", "30", "--vk-validate"});
  ASSERT_EQ(no_map.size(), 2u);
  EXPECT_NE(no_map[0].find("not made with --edges off"), std::string::npos) << no_map[0];
  // --aov geo makes the map in every mode, so its thresholds apply.
  EXPECT_TRUE(inapplicable({"a.json", "--aa", "uniform", "--aov", "geo", "g.png", "--edge-ss", "6"}).empty());
}

TEST(RenderOptions, HeatmapsAreDisplayImagesNotRadiance) {
  BatchOptions o;
  EXPECT_NE(parse({"a.json", "--aov", "rays", "r.exr"}, o).find("display image"), std::string::npos);
  BatchOptions p;
  EXPECT_EQ(parse({"a.json", "--aov", "rays", "r.png"}, p), "");
}

TEST(RenderOptions, DeviceIndexIsNotNegative) {
  BatchOptions o;
  EXPECT_NE(parse({"a.json", "--vk-device", "-1"}, o).find("cli: "), std::string::npos);
}

}  // namespace
}  // namespace zz
