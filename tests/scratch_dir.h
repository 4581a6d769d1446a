// A fresh folder for each test: its suite, name and the process id in the folder's name, so
// parallel ctest processes and repeated runs never share files; removed after the test.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace zz::test {

struct ScratchDirTest : ::testing::Test {
  std::filesystem::path dir;
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = std::filesystem::temp_directory_path() / ("zigzag_" + std::string(info->test_suite_name()) + "_" +
                                                    std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::create_directories(dir);
  }
  void TearDown() override { std::filesystem::remove_all(dir); }
};

}  // namespace zz::test
