// Shared Vulkan context for the gpu tests: validation always on, and every test must
// leave the validation message count unchanged, objects left alive on the device too
// (reported when the suite closes the context). Skips only when no device exists.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "core/error.h"
#include "gpu/device.h"

namespace zz::test {

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (context_ || !skip_reason_.empty() || !setup_error_.empty()) return;
    VulkanOptions options;
    options.validate = true;
    try {
      context_ = VulkanContext::create(options);
    } catch (const Error& e) {
      // Only a missing device skips; e.g. a missing validation layer fails the tests. Not
      // by throwing from here: gtest then ran each test into SetUp's skip, and ctest,
      // which reads "[  SKIPPED ]", counted the failed suite as skipped.
      if (std::string(e.what()).rfind("no Vulkan device", 0) == 0) skip_reason_ = e.what();
      else setup_error_ = e.what();
    }
  }
  static void TearDownTestSuite() {
    if (!context_) return;
    const int before = context_->validation_message_count();
    context_->close();  // vkDestroyDevice reports every object still alive
    EXPECT_EQ(context_->validation_message_count(), before) << "objects left alive on the device";
    context_.reset();
  }
  void SetUp() override {
    if (!setup_error_.empty()) FAIL() << "Vulkan setup failed: " << setup_error_;
    if (!context_) GTEST_SKIP() << skip_reason_;
    ASSERT_TRUE(context_->validation_enabled());
    messages_before_ = context_->validation_message_count();
  }
  void TearDown() override {
    if (context_) {
      EXPECT_EQ(context_->validation_message_count(), messages_before_) << "validation messages";
    }
  }
  VulkanContext& context() { return *context_; }

  static inline std::unique_ptr<VulkanContext> context_;
  static inline std::string skip_reason_, setup_error_;
  int messages_before_ = 0;
};

}  // namespace zz::test
