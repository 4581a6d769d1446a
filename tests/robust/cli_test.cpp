// Bad input at the command line: `zigzag render` run as a child process. Every bad input
// gives a one-line error and a non-zero exit status; never a crash (death by signal) or a
// hang (timeout); and no output image is written for a failed job. In a batch, the good
// scenes are still rendered and the exit status reports the failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "core/error.h"
#include "child_process.h"
#include "scratch_scene_dir.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

using robust::kScenes;
using robust::kZigzag;

class Cli : public robust::ScratchSceneDir {
 protected:
  Cli() : ScratchSceneDir("zz_robust_cli_") {}

  // zigzag render <args> --edges off -o DIR/{scene}.png
  std::vector<std::string> render_argv(const std::vector<std::string>& args) const {
    std::vector<std::string> argv = {kZigzag, "render"};
    argv.insert(argv.end(), args.begin(), args.end());
    for (const char* a : {"--edges", "off", "--threads", "2", "-o"}) argv.push_back(a);
    argv.push_back((dir_ / "{scene}.png").string());
    return argv;
  }
  robust::ChildResult render(const std::vector<std::string>& args, robust::ChildOptions opt = {}) const {
    return robust::run_child(render_argv(args), opt);
  }

  // The failure contract for one job.
  void expect_clean_failure(const robust::ChildResult& r, const std::string& image, const std::string& mention) const {
    EXPECT_FALSE(r.timed_out) << "hang";
    EXPECT_EQ(r.signal, 0) << "crashed by signal " << r.signal << ": " << r.err;
    ASSERT_TRUE(r.exited);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.exit_code, 2) << "internal error: " << r.err;  // main's catch-all for non-zz errors
    // One line; command-line syntax errors (CLI11) add its standard hint line.
    const std::vector<std::string> lines = robust::lines_of(r.err);
    const bool hint = lines.size() == 2 && lines[1] == "Run with --help for more information.";
    EXPECT_TRUE(lines.size() == 1 || hint) << "one-line error expected, got:\n" << r.err;
    for (const std::string& line : lines) EXPECT_LT(line.size(), 300u) << "unreadable message: " << line;
    if (!mention.empty()) {
      EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
    }
    if (!image.empty()) {
      EXPECT_FALSE(fs::exists(path(image))) << "an image was written for a failed job";
    }
  }

};

std::string base64(const void* data, size_t n) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const uint8_t*>(data);
  std::string out;
  for (size_t i = 0; i < n; i += 3) {
    const uint32_t v = uint32_t(b[i]) << 16 | (i + 1 < n ? uint32_t(b[i + 1]) << 8 : 0) | (i + 2 < n ? b[i + 2] : 0);
    out += k[(v >> 18) & 63];
    out += k[(v >> 12) & 63];
    out += i + 1 < n ? k[(v >> 6) & 63] : '=';
    out += i + 2 < n ? k[v & 63] : '=';
  }
  return out;
}

// One triangle with the given 9 position floats, drawn with `mode`.
std::string one_triangle_gltf(const float (&pos)[9], int mode = 4) {
  const std::string uri = "data:application/octet-stream;base64," + base64(pos, sizeof pos);
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
         R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":)" + std::to_string(mode) + R"(}]}],)"
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
         R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":36,"uri":")" + uri + R"("}]})";
}

std::string head_of(const fs::path& p, size_t bytes) {
  std::ifstream in(p, std::ios::binary);
  std::string s(bytes, '\0');
  in.read(s.data(), std::streamsize(bytes));
  s.resize(size_t(in.gcount()));
  return s;
}

TEST_F(Cli, GoodSceneRenders) {
  const robust::ChildResult r = render({path("good.json").string(), "-q"});
  EXPECT_TRUE(r.exited && r.exit_code == 0) << r.err;
  EXPECT_TRUE(fs::exists(path("good.png")));
  // More threads than this machine's cores, as asked: without TBB's warning (it capped them),
  // in the colour's render and in the AOV layers' centre rays alike.
  const std::string more = std::to_string(std::min(1024u, std::thread::hardware_concurrency() + 2));
  const robust::ChildResult many = robust::run_child({kZigzag, "render", path("good.json").string(), "-q", "--threads",
                                                      more, "-o", path("many.exr").string(), "--aov", "depth"});
  EXPECT_TRUE(many.exited && many.exit_code == 0) << many.err;
  EXPECT_EQ(many.err, "");
}

TEST_F(Cli, MissingAndMalformedSceneFiles) {
  struct Case {
    std::string name, bytes, mention;
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float nan_pos[9] = {0, 0, 0, 1, 0, 0, 0, nan, 0};
  const std::string glb = head_of(fs::path(ZZ_SOURCE_DIR) / "tools/fuzz/tiny.glb", 4096);
  const std::vector<Case> cases = {
      {"malformed.json", R"({"model": "default.gltf", )", "invalid JSON"},
      {"wrong_type.json", R"({"model": 5})", "model"},
      {"unknown_key.json", R"({"model": "default.gltf", "colour": 1})", "colour"},
      {"no_model.json", R"({"model": "missing.gltf"})", "not found"},
      {"nan_light.json", R"({"model": "default.gltf", "lights": [{"position": [0, 1, 0], "intensity": 1e400}]})", ""},
      {"bad_camera.json", R"({"model": "default.gltf", "camera": {"eye": [0, 0, 0], "target": [0, 0, 0]}})", "camera"},
      {"empty.gltf", "", ""},
      {"truncated.gltf", head_of(kScenes / "default.gltf", 3000), ""},
      {"garbage.gltf", std::string("\x00\xff\x13garbage", 10), ""},
      {"truncated.glb", glb.substr(0, glb.size() / 2), ""},
      {"header_only.glb", glb.substr(0, 12), ""},
      {"garbage.glb", "glTF\x02\x00\x00\x00\xff\xff\xff\x7f JSON", ""},
      {"nan_vertex.gltf", one_triangle_gltf(nan_pos), "NaN"},
      {"scene.obj", "v 0 0 0\n", "unknown scene format"},
  };
  std::vector<std::vector<std::string>> argvs;
  for (const Case& c : cases) {
    write(c.name, c.bytes);
    argvs.push_back(render_argv({path(c.name).string(), "-q"}));
  }
  // A path that does not exist, and a directory.
  fs::create_directories(path("dir.gltf"));
  argvs.push_back(render_argv({path("nope.json").string(), "-q"}));
  argvs.push_back(render_argv({path("dir.gltf").string(), "-q"}));
  const std::vector<robust::ChildResult> results = robust::run_children(argvs, {{}, 30.0});
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].name);
    expect_clean_failure(results[i], fs::path(cases[i].name).stem().string() + ".png", cases[i].mention);
  }
  expect_clean_failure(results[cases.size()], "nope.png", "not found");
  expect_clean_failure(results[cases.size() + 1], "dir.png", "");
}

// A glTF whose one accessor/buffer view/buffer/node graph is built by `edit`.
std::string hostile_gltf(const std::string& accessor, const std::string& view, const std::string& buffer,
                         const std::string& nodes = R"([{"mesh":0}])") {
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":)" + nodes +
         R"(,"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"accessors":[)" + accessor +
         R"(],"bufferViews":[)" + view + R"(],"buffers":[)" + buffer + "]}";
}

TEST_F(Cli, HostileGltfFailsQuicklyAndCleanly) {
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::string data = R"({"byteLength":36,"uri":"data:application/octet-stream;base64,)" + base64(pos, 36) + R"("})";
  const std::string view = R"({"buffer":0,"byteLength":36})";
  auto acc = [](const std::string& count) {
    return R"({"bufferView":0,"componentType":5126,"count":)" + count + R"(,"type":"VEC3"})";
  };
  // 40 levels of nodes that each instance the next one twice: 2^40 copies of a triangle.
  std::string dag = "[";
  for (int i = 0; i < 40; ++i) dag += R"({"children":[)" + std::to_string(i + 1) + "," + std::to_string(i + 1) + "]},";
  dag += R"({"mesh":0}])";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"count_2e31.gltf", hostile_gltf(acc("2147483648"), view, data)},
      {"count_2e32.gltf", hostile_gltf(acc("4294967299"), view, data)},
      {"count_negative.gltf", hostile_gltf(acc("-5"), view, data)},
      {"stride_2e31.gltf", hostile_gltf(acc("3"), R"({"buffer":0,"byteLength":36,"byteStride":2147483648})", data)},
      {"dev_zero.gltf", hostile_gltf(acc("3"), view, R"({"byteLength":36,"uri":"/dev/zero"})")},
      {"dev_zero_huge.gltf", hostile_gltf(acc("68719476736"), R"({"buffer":0,"byteLength":1099511627776})",
                                          R"({"byteLength":1099511627776,"uri":"/dev/zero"})")},
      {"self_cycle.gltf", hostile_gltf(acc("3"), view, data, R"([{"mesh":0,"children":[0,0]}])")},
      {"instancing_2e40.gltf", hostile_gltf(acc("3"), view, data, dag)},
  };
  const size_t n = robust::kSanitized ? cases.size() - 1 : cases.size();  // instancing last
  std::vector<std::vector<std::string>> argvs;
  for (size_t i = 0; i < n; ++i) {
    write(cases[i].first, cases[i].second);
    argvs.push_back(render_argv({path(cases[i].first).string(), "-q", "--width", "8", "--height", "8"}));
  }
  robust::ChildOptions opt;
  opt.timeout_s = 20.0;
  if (!robust::kSanitized) opt.address_space_limit = size_t(4) << 30;  // an explosion fails inside the child
  const std::vector<robust::ChildResult> results = robust::run_children(argvs, opt);
  for (size_t i = 0; i < n; ++i) {
    SCOPED_TRACE(cases[i].first);
    expect_clean_failure(results[i], fs::path(cases[i].first).stem().string() + ".png", "");
    // (In a sanitizer build the children run without the address-space limit, so the
  // exploding case is left out there.)
  // Running out of the 4 GiB is not a diagnosis: the loader must see the problem itself.
    EXPECT_EQ(results[i].err.find("bad_alloc"), std::string::npos) << results[i].err;
    // CPU time, not the wall clock: the children run at once on a loaded machine, each
    // waiting for the others; the 20 s timeout above catches a hang.
    EXPECT_LT(results[i].cpu_seconds, 10.0);
  }
}

TEST_F(Cli, UnsupportedPrimitiveModesAreSkippedWithAWarning) {
  // Lines only: nothing to render is a warning per primitive (the loader's documented
  // leniency), not a crash; the frame shows the background.
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int modes[] = {0, 1, 2, 3, 7, 99};
  std::vector<std::vector<std::string>> argvs;
  for (int mode : modes) {
    const std::string name = "mode" + std::to_string(mode);
    write(name + ".gltf", one_triangle_gltf(pos, mode));
    argvs.push_back(render_argv({path(name + ".gltf").string(), "--width", "8", "--height", "8"}));
  }
  const std::vector<robust::ChildResult> results = robust::run_children(argvs, {{}, 30.0});
  for (size_t i = 0; i < results.size(); ++i) {
    const robust::ChildResult& r = results[i];
    SCOPED_TRACE(modes[i]);
    EXPECT_TRUE(r.exited) << "signal " << r.signal;
    EXPECT_NE(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("mode"), std::string::npos) << r.err;
    if (r.exit_code != 0) {
      EXPECT_FALSE(fs::exists(path("mode" + std::to_string(modes[i]) + ".png")));
    }
  }
}

TEST_F(Cli, BadOptions) {
  const std::string good = path("good.json").string();
  const std::vector<std::vector<std::string>> cases = {
      {good, "--width", "0"},          {good, "--width", "-1"},       {good, "--width", "20000"},
      {good, "--height", "0"},         {good, "--height", "abc"},     {good, "--frobnicate"},
      {good, "--tables", "nope"},      {good, "--camera", "99"},      {good, "--camera", "-1"},
      {good, "--camera", "x"},         {good, "--aa", "magic"},       {good, "--eps", "-1"},
      {good, "--spp", "0"},            {good, "--aa", "uniform", "--spp", "7"},
      {good, "--filter", "gauss"},     {good, "--geo-policy", "x"},   {good, "--max-depth", "1000"},
      {good, "--exposure", "0"},       {good, "--threads", "-3"}};
  std::vector<std::vector<std::string>> argvs;
  for (std::vector<std::string> args : cases) {
    args.push_back("-q");
    argvs.push_back(render_argv(args));
  }
  const std::vector<robust::ChildResult> results = robust::run_children(argvs, {{}, 30.0});
  for (size_t i = 0; i < cases.size(); ++i) {
    std::string label;
    for (const std::string& a : cases[i]) label += a + " ";
    SCOPED_TRACE(label);
    expect_clean_failure(results[i], "good.png", "");
  }
}

// A mistyped command is named, with the commands there are (CLI11 alone said "A
// subcommand is required").
TEST_F(Cli, AnUnknownCommandIsNamed) {
  const robust::ChildResult r = robust::run_child({kZigzag, "rendr", path("good.json").string()});
  expect_clean_failure(r, "", "unknown command 'rendr' (the commands: render, view");
}

TEST_F(Cli, OneBadSceneInABatchStillRendersTheOthers) {
  write("other.json", R"({"model": "default.gltf", "width": 16, "height": 12})");
  write("broken.json", R"({"model": )");
  const robust::ChildResult r =
      render({path("good.json").string(), path("broken.json").string(), path("other.json").string(), "-q"});
  EXPECT_TRUE(r.exited) << "signal " << r.signal;
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(fs::exists(path("good.png")));
  EXPECT_TRUE(fs::exists(path("other.png")));
  EXPECT_FALSE(fs::exists(path("broken.png")));
  EXPECT_NE(r.err.find("broken.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 of 3 jobs failed"), std::string::npos) << r.err;
}

TEST_F(Cli, UnwritableOutputIsAnError) {
  std::vector<std::string> argv = {kZigzag, "render", path("good.json").string(), "--edges", "off", "-q",
                                   "-o", "/proc/zz_no_such_dir/out.png"};
  const robust::ChildResult r = robust::run_child(argv, {{}, 30.0});
  EXPECT_TRUE(r.exited) << "signal " << r.signal;
  EXPECT_EQ(r.exit_code, kUsageExit) << r.err;  // found before the scene loads
}

// ---- memory ---------------------------------------------------------------------------

TEST_F(Cli, FrameTooLargeForTheAddressSpaceFailsEarlyWithAClearMessage) {
  // 16384^2 pixels need 16384^2 * (12 + 2) bytes = 3.5 GiB of film alone; the child may
  // map 1 GiB. Expected: a one-line error naming the memory needed, exit 1, no image, and
  // no attempt to render (well inside the timeout).
  if (robust::kSanitized) GTEST_SKIP() << "RLIMIT_AS cannot be combined with ASan's shadow memory";
  robust::ChildOptions opt;
  opt.address_space_limit = size_t(1) << 30;
  opt.timeout_s = 60.0;
  const robust::ChildResult r = render({path("good.json").string(), "--width", "16384", "--height", "16384", "-q"}, opt);
  expect_clean_failure(r, "good.png", "memory");
}

TEST_F(Cli, MemoryLimitFromTheEnvironmentIsHonoured) {
  // The same check against an explicit budget (bytes): 4096^2 needs 224 MiB of film.
  robust::ChildOptions opt;
  opt.env = {{"ZIGZAG_MEMORY_LIMIT", std::to_string(64u << 20)}};
  const robust::ChildResult r = render({path("good.json").string(), "--width", "4096", "--height", "4096", "-q"}, opt);
  expect_clean_failure(r, "good.png", "(ZIGZAG_MEMORY_LIMIT=67108864, less the ");
  // A value that is no memory size is refused before anything loads, naming the variable
  // (strtoull read "4GB" as 4 bytes: every render failed for want of memory).
  opt.env = {{"ZIGZAG_MEMORY_LIMIT", "4GB"}};
  const robust::ChildResult bad = render({path("good.json").string(), "--width", "64", "-q"}, opt);
  expect_clean_failure(bad, "good.png", "ZIGZAG_MEMORY_LIMIT=4GB: not a memory size");
  EXPECT_EQ(bad.exit_code, kUsageExit);
}

// A merge holds the frame and one part at a time: it read every part before merging, 3.3x
// the frame's radiance at peak (review), so a farm's 16384^2 frame needed ~10 GB. Its need
// is checked against the budget before any pixel is read.
TEST_F(Cli, MergeHoldsTheFrameAndOnePartAtATime) {
  if (robust::kSanitized) GTEST_SKIP() << "ASan inflates RSS: the bound is for normal builds";
  constexpr int kSide = 3072, kStrips = 8;
  std::vector<std::string> merge = {kZigzag, "merge"};
  for (int i = 0; i < kStrips; ++i) {
    const int y0 = i * kSide / kStrips, y1 = (i + 1) * kSide / kStrips;
    merge.push_back(path("part" + std::to_string(i) + ".exr").string());
    const robust::ChildResult r = robust::run_child(
        {kZigzag, "render", path("good.json").string(), "--width", std::to_string(kSide), "--height",
         std::to_string(kSide), "--aa", "none", "--edges", "off", "--region",
         "0," + std::to_string(y0) + "," + std::to_string(kSide) + "," + std::to_string(y1), "-q", "-o", merge.back()});
    ASSERT_TRUE(r.exited && r.exit_code == 0) << r.err;
  }
  merge.insert(merge.end(), {"-o", path("merged.exr").string()});
  robust::ChildOptions tight;
  tight.env = {{"ZIGZAG_MEMORY_LIMIT", std::to_string(64u << 20)}};
  expect_clean_failure(robust::run_child(merge, tight), "merged.exr", "memory");
  // The process's own memory (shared libraries mapped in) is measured apart: 130 MiB here.
  const robust::ChildResult idle = robust::run_child({kZigzag, "--version"});
  const robust::ChildResult r = robust::run_child(merge, {{}, 120.0});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << r.err;
  // The frame's film is 3072^2 x 14 bytes = 126 MiB, a part 16 MiB: measured 155 MiB above
  // the idle process; with every part read first it was 248 MiB.
  const double beyond_mib = double(r.max_rss_kb - idle.max_rss_kb) / 1024.0;
  std::printf("[ memory ] merge of %d parts of %d^2: peak RSS %.1f MiB beyond the idle process's %.1f MiB, %.2f s\n",
              kStrips, kSide, beyond_mib, idle.max_rss_kb / 1024.0, r.seconds);
  EXPECT_LT(beyond_mib, 126.0 * 1.5);
}

TEST_F(Cli, PeakMemoryOfARenderIsBounded) {
  // The room (9 lights, mirror) at 1024^2: film 14 MiB + scene + BVH + per-thread
  // buffers. Bound: 200 MiB (measured 145 MiB on Debian 12, most of it shared libraries); a leak or a per-pixel allocation
  // would blow through it.
  if (robust::kSanitized) GTEST_SKIP() << "ASan inflates RSS: the bound is for normal builds";
  const robust::ChildResult r =
      robust::run_child({kZigzag, "render", (kScenes / "room.json").string(), "--edges", "off", "-q", "--width",
                         "1024", "--height", "1024", "--aa", "none", "-o", path("room.png").string()},
                        {{}, 120.0});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << r.err;
  std::printf("[ memory ] room 1024^2 --aa none: peak RSS %.1f MiB in %.2f s\n", r.max_rss_kb / 1024.0, r.seconds);
  EXPECT_LT(r.max_rss_kb, 200 * 1024);
}

}  // namespace
}  // namespace zz
