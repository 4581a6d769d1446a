// `zigzag info`: the facts a farm plans jobs from, as JSON and as text.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli.h"

namespace zz {
namespace {

nlohmann::json info_json(const std::string& args, int expected_exit = 0) {
  const auto r = test::run_command(test::zigzag_binary() + " info --json " + args);
  EXPECT_EQ(r.exit_code, expected_exit) << r.output;
  // stderr comes first (error lines); stdout is the JSON array alone.
  const size_t start = r.output.rfind("[\n", 0) == 0 ? 0 : r.output.find("\n[\n") + 1;
  return nlohmann::json::parse(r.output.substr(start));
}

TEST(InfoCommand, StaticSceneAsJson) {
  const nlohmann::json all = info_json(test::source_path("scenes/room.json"));
  ASSERT_EQ(all.size(), 1u);
  const nlohmann::json& j = all[0];
  EXPECT_EQ(j["scene"], "room");
  EXPECT_EQ(j["width"], 1024);
  EXPECT_EQ(j["height"], 1024);
  EXPECT_EQ(j["camera_count"], 1);
  EXPECT_EQ(j["cameras"], nlohmann::json({"front"}));
  EXPECT_EQ(j["animated"], false);
  EXPECT_EQ(j["fps"], 24.0);
  EXPECT_EQ(j["frames"], nlohmann::json({0, 0}));
  EXPECT_EQ(j["frame_count"], 1);
  EXPECT_EQ(j["triangles"], 10196);
  EXPECT_EQ(j["lights"], 9);
}

TEST(InfoCommand, DefaultsAreTheOnesRenderUses) {
  // A rig without width/height: render's default 512².
  const nlohmann::json j = info_json(test::source_path("scenes/default.json"))[0];
  EXPECT_EQ(j["width"], 512);
  EXPECT_EQ(j["height"], 512);
}

// A farm splits a frame into regions by these sizes: with --width or --height they are
// what `render` with the same option makes (a side left out follows the camera's aspect).
TEST(InfoCommand, SizesFollowWidthAndHeightAsRenderDoes) {
  // A rig without width/height whose camera is twice as wide as tall.
  const std::filesystem::path rig =
      std::filesystem::temp_directory_path() / ("zigzag_info_wide_" + std::to_string(::getpid()) + ".json");
  std::ofstream(rig) << R"({"model": ")" << test::source_path("scenes/default.gltf")
                     << R"(", "camera": {"eye": [0, 1, 6], "target": [0, 0, 0], "aspect": 2}})";
  const nlohmann::json given = info_json(rig.string())[0];
  EXPECT_EQ(given["camera_sizes"][0], nlohmann::json({512, 256}));
  const nlohmann::json narrow = info_json("--width 300 " + rig.string())[0];
  EXPECT_EQ(narrow["width"], 300);
  EXPECT_EQ(narrow["height"], 150);
  EXPECT_EQ(info_json("--height 40 " + rig.string())[0]["camera_sizes"][0], nlohmann::json({80, 40}));
  EXPECT_EQ(info_json("--width 300 --height 40 " + rig.string())[0]["camera_sizes"][0], nlohmann::json({300, 40}));
  // The very size render makes.
  const std::string png = rig.string() + ".png";
  const auto r = test::run_command(test::zigzag_binary() + " render -q --aa none --edges off --width 30 -o " + png +
                                   " " + rig.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto probe = test::run_command("python3 -c \"import struct; f=open('" + png +
                                       "','rb').read(24); print(*struct.unpack('>II', f[16:24]))\"");
  EXPECT_EQ(probe.output, "30 15\n");
  EXPECT_NE(test::run_command(test::zigzag_binary() + " info --width 0 " + rig.string()).exit_code, 0);
  std::filesystem::remove(rig);
  std::filesystem::remove(png);
}

// The files a scene is read from, so a farm can tell a finished frame whose model, buffers
// or textures changed since.
TEST(InfoCommand, ListsTheFilesTheSceneIsReadFrom) {
  const nlohmann::json j = info_json(test::source_path("scenes/default.json"))[0];
  std::vector<std::string> names;
  for (const auto& f : j["files"]) names.push_back(std::filesystem::path(f.get<std::string>()).filename().string());
  EXPECT_EQ(names, std::vector<std::string>({"default.json", "default.gltf", "default.bin"}));
  for (const auto& f : j["files"]) EXPECT_TRUE(std::filesystem::is_regular_file(f.get<std::string>())) << f;
}

TEST(InfoCommand, BadSceneReportedOthersListed) {
  const nlohmann::json all =
      info_json(test::source_path("scenes/nope.json") + " " + test::source_path("scenes/default.json"), 1);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_TRUE(all[0].contains("error"));
  EXPECT_NE(all[0]["error"].get<std::string>().find("not found"), std::string::npos);
  EXPECT_EQ(all[1]["scene"], "default");
}

TEST(InfoCommand, HumanReadableWithoutJson) {
  const auto r = test::run_command(test::zigzag_binary() + " info " + test::source_path("scenes/room.json"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1024x1024"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("10196 triangles, 9 lights"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("front (1024x1024)"), std::string::npos) << r.output;  // each camera's size
  EXPECT_NE(r.output.find("scenes/room.gltf"), std::string::npos) << r.output;    // the files
  EXPECT_FALSE(nlohmann::json::accept(r.output));
}

}  // namespace
}  // namespace zz
