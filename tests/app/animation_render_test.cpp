// Animated scenes through `zigzag render`: --frame / --time / --fps pick the scene time,
// frames differ, the same time gives the same pixels, {frame:04} names the output.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "cli.h"
#include "core/error.h"
#include "render/image_io.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct AnimationRender : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("zigzag_animation_test_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }

  // `pattern` is what -o gets; `output` the file it expands to.
  std::vector<float> render(const std::string& options, const std::string& output, std::string pattern = "") {
    if (pattern.empty()) pattern = output;
    const auto r = test::run_command(test::zigzag_binary() + " render " + test::source_path("scenes/animated.json") +
                                     " --width 64 --height 64 --edges off -q " + options + " -o " +
                                     (dir / pattern).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    int w = 0, h = 0;
    return fs::exists(dir / output) ? read_rgb_float(dir / output, w, h) : std::vector<float>{};
  }
};

TEST_F(AnimationRender, FramesDifferAndTimeMatchesFrame) {
  const std::vector<float> f0 = render("--frame 0", "f0000.exr", "f{frame:04}.exr");
  const std::vector<float> f24 = render("--frame 24", "f0024.exr", "f{frame:04}.exr");
  ASSERT_TRUE(fs::exists(dir / "f0000.exr"));
  ASSERT_TRUE(fs::exists(dir / "f0024.exr"));
  ASSERT_EQ(f0.size(), size_t(64 * 64 * 3));
  ASSERT_EQ(f0.size(), f24.size());
  EXPECT_NE(std::memcmp(f0.data(), f24.data(), f0.size() * sizeof(float)), 0);
  // t = 24 / 24 = 1 s, and frame 12 at 12 fps is the same instant.
  const std::vector<float> t1 = render("--time 1", "t.exr");
  const std::vector<float> f12 = render("--frame 12 --fps 12", "f12.exr");
  ASSERT_EQ(t1.size(), f24.size());
  EXPECT_EQ(std::memcmp(t1.data(), f24.data(), t1.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(f12.data(), f24.data(), f12.size() * sizeof(float)), 0);
  // A time within 1e-6 of a frame names it ({frame}, the stats), so it is that frame
  // exactly: 1/24 s written with 7 digits rendered 6 pixels off --frame 1's file of one name.
  const std::vector<float> f1 = render("--frame 1", "f0001.exr", "f{frame:04}.exr");
  const std::vector<float> near = render("--time 0.0416667", "n0001.exr", "n{frame:04}.exr");
  ASSERT_EQ(near.size(), f1.size());
  EXPECT_EQ(std::memcmp(near.data(), f1.data(), f1.size() * sizeof(float)), 0);
}

TEST_F(AnimationRender, FrameAndTimeAreExclusive) {
  const auto r = test::run_command(test::zigzag_binary() + " render " + test::source_path("scenes/animated.json") +
                                   " --frame 1 --time 1 -q -o " + (dir / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("excludes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// {frame} names a frame; a time between two frames has none, and rounding it would let two
// times overwrite one file. A time on a frame names that frame.
TEST_F(AnimationRender, TimeBetweenFramesNamesNoFrame) {
  const std::string base = test::zigzag_binary() + " render " + test::source_path("scenes/animated.json") +
                           " --width 16 --height 16 --edges off -q ";
  const auto between = test::run_command(base + "--time 1.01 -o " + (dir / "t{frame}.png").string());
  EXPECT_EQ(between.exit_code, kUsageExit) << between.output;
  EXPECT_NE(between.output.find("between frames"), std::string::npos) << between.output;
  EXPECT_FALSE(fs::exists(dir / "t24.png"));
  const auto on_frame = test::run_command(base + "--time 1 -o " + (dir / "t{frame}.png").string() + " --stats " +
                                          (dir / "t{frame}.json").string());
  EXPECT_EQ(on_frame.exit_code, 0) << on_frame.output;
  EXPECT_TRUE(fs::exists(dir / "t24.png"));
  const std::string on_frame_stats = text_of(dir / "t24.json");  // names the frame the file is named after
  EXPECT_NE(on_frame_stats.find("\"frame\": 24,"), std::string::npos) << on_frame_stats;
  // Without {frame} any time renders; its stats give the time, and no frame.
  const auto named = test::run_command(base + "--time 1.01 -o " + (dir / "t.png").string() + " --stats " +
                                       (dir / "t.json").string());
  EXPECT_EQ(named.exit_code, 0) << named.output;
  const std::string stats = text_of(dir / "t.json");
  EXPECT_NE(stats.find("\"frame\": null"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"scene_time_s\": 1.01"), std::string::npos) << stats;
}

// Past either end of the animation the pose is held: rendered, with a warning, as it is
// usually a wrong --frame or --fps.
TEST_F(AnimationRender, OutsideTheAnimationWarns) {
  auto warnings = [&](const std::string& options) {
    const auto r = test::run_command(test::zigzag_binary() + " render " + test::source_path("scenes/animated.json") +
                                     " --width 16 --height 16 --edges off " + options + " -o " +
                                     (dir / "w.png").string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.output.find("warning") == std::string::npos ? std::string() : r.output;
  };
  EXPECT_EQ(warnings("--frame 0"), "");
  EXPECT_EQ(warnings("--frame 47"), "");  // the range's last frame (0..47)
  EXPECT_EQ(warnings("--time 2"), "");    // the last keyframe
  EXPECT_NE(warnings("--frame 100").find("outside the scene's frames 0..47"), std::string::npos);
  EXPECT_NE(warnings("--frame 40 --fps 12").find("past the animation's end"), std::string::npos);
  EXPECT_NE(warnings("--time 5").find("past the animation's end"), std::string::npos);
}

}  // namespace
}  // namespace zz
