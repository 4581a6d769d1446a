// `zigzag info`: the facts a farm plans jobs from, as JSON and as text.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

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
  EXPECT_FALSE(nlohmann::json::accept(r.output));
}

}  // namespace
}  // namespace zz
