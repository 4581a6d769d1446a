// A per-test scratch folder holding the default model under a small rig of our own
// (good.json, 24x16): the black-box CLI tests run `zigzag` on files they write there.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace zz::robust {

namespace fs = std::filesystem;

inline const std::string kZigzag = std::string(ZZ_BINARY_DIR) + "/zigzag";
inline const fs::path kScenes = fs::path(ZZ_SOURCE_DIR) / "scenes";

class ScratchSceneDir : public testing::Test {
 protected:
  // `prefix` names the folder, so parallel suites (and build dirs) never share one.
  explicit ScratchSceneDir(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (prefix_ + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(kScenes / "default.gltf", dir_ / "default.gltf");
    fs::copy_file(kScenes / "default.bin", dir_ / "default.bin");
    write("good.json", R"({"model": "default.gltf", "width": 24, "height": 16})");
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path path(const std::string& name) const { return dir_ / name; }
  void write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
  }

  fs::path dir_;

 private:
  std::string prefix_;
};

}  // namespace zz::robust
