// Replays the loader fuzzers' inputs with the compiler of this build (gcc, or the
// ASan/UBSan build): the seed corpus tools/fuzz/corpus/FORMAT/ and the regression inputs
// tools/fuzz/regressions/FORMAT/ (every input a fuzzer ever crashed on, named by what it
// found). fuzz_loader.cpp aborts on a contract violation, so a test that returns passed.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_loader.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

int replay(const fs::path& dir, const std::string& format) {
  if (!fs::is_directory(dir)) return 0;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    std::ifstream in(f, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    fuzz::load_input(bytes.data(), bytes.size(), format);
  }
  return int(files.size());
}

class FuzzReplay : public testing::TestWithParam<std::string> {};

TEST_P(FuzzReplay, SeedCorpus) {
  EXPECT_GT(replay(fs::path(ZZ_SOURCE_DIR) / "tools/fuzz/corpus" / GetParam(), GetParam()), 0);
}

TEST_P(FuzzReplay, Regressions) {
  replay(fs::path(ZZ_SOURCE_DIR) / "tools/fuzz/regressions" / GetParam(), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Formats, FuzzReplay, testing::Values("gltf", "glb", "json"));

}  // namespace
}  // namespace zz
