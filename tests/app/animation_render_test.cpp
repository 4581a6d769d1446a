// Animated scenes through `zigzag render`: --frame / --time / --fps pick the scene time,
// frames differ, the same time gives the same pixels, {frame:04} names the output.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>

#include "cli.h"
#include "render/image_io.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

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
}

TEST_F(AnimationRender, FrameAndTimeAreExclusive) {
  const auto r = test::run_command(test::zigzag_binary() + " render " + test::source_path("scenes/animated.json") +
                                   " --frame 1 --time 1 -q -o " + (dir / "x.png").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("excludes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

}  // namespace
}  // namespace zz
