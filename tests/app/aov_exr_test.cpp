// `zigzag render -o out.exr --aov NAME` (no file): the AOVs as raw channels of the same
// EXR, through the real binary (the visibility map on lavapipe with validation on), read
// back with OpenImageIO by channel name and checked against the stats, the PNG heatmaps,
// the scene's floor in closed form, and region parts merged with `zigzag merge`.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "core/error.h"
#include "cli.h"
#include "../scratch_dir.h"
#include "render/aov.h"
#include "render/image_io.h"
#include "scene/loader.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

// An EXR's channels by name, each width*height floats over its data window.
struct Layers {
  int width = 0, height = 0;
  std::vector<std::string> names;  // as stored
  std::map<std::string, std::vector<float>> channels;
  float at(const std::string& name, int x, int y) const { return channels.at(name)[size_t(y) * width + x]; }
};

Layers read_layers(const fs::path& path) {
  Layers l;
  auto in = OIIO::ImageInput::open(path.string());
  EXPECT_TRUE(in) << path;
  if (!in) return l;
  const OIIO::ImageSpec& spec = in->spec();
  l.width = spec.width;
  l.height = spec.height;
  l.names = spec.channelnames;
  std::vector<float> all(size_t(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()));
  for (int c = 0; c < spec.nchannels; ++c) {
    std::vector<float>& v = l.channels[spec.channelnames[size_t(c)]];
    v.resize(size_t(spec.width) * spec.height);
    for (size_t p = 0; p < v.size(); ++p) v[p] = all[p * size_t(spec.nchannels) + size_t(c)];
  }
  return l;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

const char* kAllLayers = " --aov rays --aov level --aov geo --aov depth --aov normal --aov albedo ";

struct AovExrTest : test::ScratchDirTest {

  // 150 x 130: partial tiles at both far edges.
  static constexpr int kW = 150, kH = 130;

  std::string scene() const { return test::source_path("scenes/default.json"); }

  test::CommandResult run(const std::string& options) const {
    return test::run_command(test::zigzag_binary() + " render " + scene() + " --width 150 --height 130 -q " + options);
  }
  fs::path render(const std::string& options, const std::string& output) const {
    const auto r = run(options + " --vk-validate -o " + (dir / output).string());
    EXPECT_EQ(r.exit_code, 0) << options << "\n" << r.output;
    return dir / output;
  }
  nlohmann::json stats(const std::string& name) const {
    std::ifstream f(dir / name);
    return nlohmann::json::parse(f);
  }
};

TEST_F(AovExrTest, AllLayersHaveTheDocumentedNamesAndValues) {
  const fs::path exr = render(std::string(kAllLayers) + "--aov rays " + (dir / "rays.png").string() + " --aov geo " +
                                  (dir / "geo.png").string() + " --stats " + (dir / "s.json").string(),
                              "all.exr");
  const Layers l = read_layers(exr);
  ASSERT_EQ(l.width, kW);
  ASSERT_EQ(l.height, kH);
  std::vector<std::string> names = l.names;
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth", "geo",
                                             "level", "normal.X", "normal.Y", "normal.Z", "rays"}));

  // rays: the numbers the heatmap PNG draws, and together the stats' ray counts. The
  // box filter's pixel owns one corner ray (its top-left) plus its levels 2-3 rays.
  const nlohmann::json s = stats("s.json");
  double sum = 0;
  for (float r : l.channels.at("rays")) {
    ASSERT_EQ(r, std::floor(r));
    ASSERT_GE(r, 1.0f);
    ASSERT_LE(r, 25.0f);  // 1 corner + 4 (level 2) + 4 in each of 5 zones (level 3)
    sum += r;
  }
  const double pixels = double(kW) * kH;
  const auto& by_level = s["adaptive"]["by_level"];
  EXPECT_NEAR(sum, pixels * (1.0 + by_level[1].get<double>() + by_level[2].get<double>()), 0.5);
  int hw = 0, hh = 0;
  const std::vector<float> heat = read_rgb_float(dir / "rays.png", hw, hh);
  ASSERT_EQ(hw, kW);
  ASSERT_GT(hh, kH);  // the legend band below
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      uint8_t rgb[3];
      ray_count_colour(int(l.at("rays", x, y)), rgb);
      const float* p = &heat[(size_t(y) * kW + x) * 3];
      for (int c = 0; c < 3; ++c) ASSERT_EQ(std::lround(p[c] * 255.0f), rgb[c]) << x << "," << y;
    }

  // level: 1..3, and as many refined pixels as the stats report.
  size_t refined = 0;
  for (float v : l.channels.at("level")) {
    ASSERT_TRUE(v == 1.0f || v == 2.0f || v == 3.0f) << v;
    refined += v > 1.0f;
  }
  EXPECT_NEAR(double(refined), pixels * s["adaptive"]["level2_fraction"].get<double>(), 0.5);

  // geo: 0/1, the PNG visibility map's white pixels.
  int gw = 0, gh = 0;
  const std::vector<float> geo_png = read_rgb_float(dir / "geo.png", gw, gh);
  size_t flagged = 0;
  for (size_t i = 0; i < l.channels.at("geo").size(); ++i) {
    const float g = l.channels.at("geo")[i];
    ASSERT_TRUE(g == 0.0f || g == 1.0f);
    ASSERT_EQ(g, geo_png[i * 3] > 0.5f ? 1.0f : 0.0f) << i;
    flagged += g == 1.0f;
  }
  EXPECT_GT(flagged, 0u);
  EXPECT_NEAR(double(flagged), pixels * s["geo_fraction"].get<double>(), 0.5);
  EXPECT_EQ(s["aov"]["primary_hit_rays"].get<uint64_t>() >= uint64_t(pixels), true);

  // depth/normal/albedo: the floor (the plane y = 0, normal +y, a checker of two base
  // colours) at the bottom row's centre pixel, against the ray-plane distance; misses
  // above the floor's far edge hold +inf and zeros.
  const Scene sc = load_scene(scene(), LoadOptions{});
  const CameraRays rays(sc.cameras[0], kW, kH);
  const int fx = kW / 2, fy = kH - 1;
  const glm::vec3 d = rays.direction(fx + 0.5f, fy + 0.5f);
  const float t = -rays.origin.y / d.y;
  EXPECT_NEAR(l.at("depth", fx, fy), t, t * 1e-4f);
  EXPECT_NEAR(l.at("normal.X", fx, fy), 0.0f, 1e-6f);
  EXPECT_NEAR(l.at("normal.Y", fx, fy), 1.0f, 1e-6f);
  EXPECT_NEAR(l.at("normal.Z", fx, fy), 0.0f, 1e-6f);
  const glm::vec3 albedo(l.at("albedo.R", fx, fy), l.at("albedo.G", fx, fy), l.at("albedo.B", fx, fy));
  EXPECT_TRUE(albedo == glm::vec3(0.8f, 0.8f, 0.8f) || albedo == glm::vec3(0.2f, 0.2f, 0.25f))
      << albedo.r << " " << albedo.g << " " << albedo.b;
  size_t misses = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float depth = l.at("depth", x, y);
      const glm::vec3 n(l.at("normal.X", x, y), l.at("normal.Y", x, y), l.at("normal.Z", x, y));
      const glm::vec3 a(l.at("albedo.R", x, y), l.at("albedo.G", x, y), l.at("albedo.B", x, y));
      if (std::isinf(depth)) {
        ++misses;
        ASSERT_GT(depth, 0.0f);
        ASSERT_EQ(n, glm::vec3(0.0f));
        ASSERT_EQ(a, glm::vec3(0.0f));
      } else {
        ASSERT_GT(depth, 0.0f);
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << x << "," << y;
        // Turned towards the camera.
        ASSERT_LT(glm::dot(n, rays.direction(x + 0.5f, y + 0.5f)), 0.0f) << x << "," << y;
      }
    }
  EXPECT_GT(misses, size_t(kW));  // the background above the floor
  EXPECT_LT(misses, size_t(kW) * kH / 2);
}

TEST_F(AovExrTest, ColourIsBitIdenticalWithLayersOn) {
  const Layers plain = read_layers(render("", "plain.exr"));
  const Layers with = read_layers(render(kAllLayers, "with.exr"));
  ASSERT_EQ(plain.names, (std::vector<std::string>{"R", "G", "B"}));
  for (const char* c : {"R", "G", "B"}) EXPECT_TRUE(same_bits(plain.channels.at(c), with.channels.at(c))) << c;
}

TEST_F(AovExrTest, UniformRaysChannelSumsToThePrimaryRays) {
  // 4 stratified rays in every pixel, no padding (each 64-wide tile row is 256 points).
  const fs::path exr = render("--aa uniform --spp 4 --aov rays --aov level --stats " + (dir / "s.json").string(),
                              "u.exr");
  const Layers l = read_layers(exr);
  double sum = 0;
  for (float r : l.channels.at("rays")) sum += r;
  for (float v : l.channels.at("level")) ASSERT_EQ(v, 1.0f);
  EXPECT_EQ(sum, stats("s.json")["rays"]["primary"].get<double>());
  EXPECT_EQ(sum, 4.0 * kW * kH);
}

TEST_F(AovExrTest, RegionPartsMergeIntoTheFullFrameBitForBit) {
  const Layers full = read_layers(render(kAllLayers, "full.exr"));
  std::string parts;
  const std::vector<std::string> regions = {"0,0,77,61", "77,0,150,61", "0,61,93,130", "93,61,150,130"};
  const char* names[] = {"p0.exr", "p1.exr", "p2.exr", "p3.exr"};
  for (size_t i = 0; i < regions.size(); ++i) {
    parts += ' ';
    parts += render(std::string(kAllLayers) + "--region " + regions[i], names[i]).string();
  }
  const auto m = test::run_command(test::zigzag_binary() + " merge" + parts + " -o " + (dir / "m.exr").string());
  ASSERT_EQ(m.exit_code, 0) << m.output;
  const Layers merged = read_layers(dir / "m.exr");
  EXPECT_EQ(merged.names, full.names);
  for (const auto& [name, values] : full.channels) EXPECT_TRUE(same_bits(merged.channels.at(name), values)) << name;

  // A part without the layers (or with others) is refused.
  const fs::path bare = render("--region 93,61,150,130", "bare.exr");
  const fs::path fewer = render("--aov depth --region 93,61,150,130", "fewer.exr");
  for (const fs::path& odd : {bare, fewer}) {
    const std::string three = std::string(" ") + (dir / "p0.exr").string() + " " + (dir / "p1.exr").string() + " " +
                              (dir / "p2.exr").string() + " " + odd.string();
    const auto r = test::run_command(test::zigzag_binary() + " merge" + three + " -o " + (dir / "bad.exr").string());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("has the AOV channels"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad.exr"));
  }
}

TEST_F(AovExrTest, BadInvocationsFailBeforeTheSceneLoads) {
  // A scene path that does not exist: the error must come from the options, not the load.
  struct Case {
    std::string options;
    std::string message;
  };
  const std::string missing = (dir / "no_such_scene.json").string();
  const std::vector<Case> cases = {
      {"-o " + (dir / "x.exr").string() + " --aov zdepth",
       "--aov zdepth: unknown AOV (valid: rays, level, geo, depth, normal, albedo)"},
      {"-o " + (dir / "x.png").string() + " --aov depth", "must be an .exr"},
      {"-o " + (dir / "x.png").string() + " --aov rays", "or give a file: --aov rays FILE.png"},
      {"-o " + (dir / "x.exr").string() + " --aov normal " + (dir / "n.png").string(), "has no image of its own"},
  };
  for (const Case& c : cases) {
    const auto r = test::run_command(test::zigzag_binary() + " render " + missing + " -q " + c.options);
    EXPECT_EQ(r.exit_code, kUsageExit) << c.options << ": " << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.options << ": " << r.output;
    EXPECT_EQ(r.output.find("no_such_scene"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    EXPECT_FALSE(fs::exists(dir / "x.png"));
  }
  const auto help = test::run_command(test::zigzag_binary() + " render --help");
  EXPECT_NE(help.output.find("rays, level, geo, depth, normal, albedo"), std::string::npos) << help.output;
}

TEST_F(AovExrTest, HeatmapFilesStillWork) {
  const auto r = run("--edges off -o " + (dir / "x.png").string() + " --aov rays " + (dir / "r.png").string() +
                     " --aov levels " + (dir / "l.png").string() + " --aov level " + (dir / "l2.png").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  int w = 0, h = 0;
  read_rgb_float(dir / "l.png", w, h);
  EXPECT_EQ(w, kW);
  EXPECT_EQ(h, kH);
  std::ifstream a(dir / "l.png", std::ios::binary), b(dir / "l2.png", std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}), std::string(std::istreambuf_iterator<char>(b), {}));
}

}  // namespace
}  // namespace zz
