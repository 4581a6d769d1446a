#include <gtest/gtest.h>
#include <sys/resource.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "gpu/resources.h"
#include "gpu_fixture.h"

namespace zz::test {
namespace {

using DeviceTest = GpuTest;

TEST_F(DeviceTest, CreatesDeviceWithGraphicsComputeQueue) {
  EXPECT_FALSE(context().device_name().empty());
  EXPECT_NE(context().device(), VK_NULL_HANDLE);
  EXPECT_GE(context().properties().apiVersion, VK_API_VERSION_1_3);
}

TEST_F(DeviceTest, HostVisibleBufferRoundTrip) {
  Buffer b = create_buffer(context(), 64, VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                           VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  ASSERT_NE(b.mapped, nullptr);
  context().run_commands([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, b.buffer, 0, 64, 0xA5A5A5A5u); });
  invalidate(b);
  EXPECT_EQ(static_cast<const uint32_t*>(b.mapped)[15], 0xA5A5A5A5u);
}

TEST_F(DeviceTest, SubmitsFromSeveralThreadsAtOnce) {
  // The context serialises its queue and pool itself: callers on any thread take no lock.
  // Validation (on in this fixture) reports any unsynchronised use as a message.
  constexpr int kThreads = 4, kRounds = 25;
  std::vector<Buffer> buffers;
  for (int t = 0; t < kThreads; ++t)
    buffers.push_back(create_buffer(context(), 256, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT));
  std::vector<std::string> errors(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      try {
        for (int round = 0; round < kRounds; ++round) {
          const uint32_t value = uint32_t(t * 1000 + round);
          context().run_commands([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffers[t].buffer, 0, 256, value); });
          invalidate(buffers[t]);
          if (static_cast<const uint32_t*>(buffers[t].mapped)[63] != value) throw Error("wrong value after fill");
          if (round % 8 == 0) context().wait_idle();
        }
      } catch (const std::exception& e) {
        errors[t] = e.what();
      }
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(errors[t], "") << "thread " << t;
}

TEST(VkCheck, NamesTheCallAndTheResult) {
  EXPECT_NO_THROW(vk_check(VK_SUCCESS, "vkQueueSubmit"));
  try {
    vk_check(VK_ERROR_DEVICE_LOST, "vkQueueSubmit");
    ADD_FAILURE() << "expected zz::Error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("vkQueueSubmit"), std::string::npos) << what;
    EXPECT_NE(what.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << what;
  }
  EXPECT_STREQ(vk_result_name(VK_ERROR_OUT_OF_DATE_KHR), "VK_ERROR_OUT_OF_DATE_KHR");
  EXPECT_STREQ(vk_result_name(VK_TIMEOUT), "VK_TIMEOUT");
}

// Out of memory says so; under an address-space limit (here one too large to bind) a
// host-side failure also names the limit, a GPU's own memory never does.
TEST(VkCheck, OutOfMemorySaysSoAndOnlyTheHostSideNamesUlimit) {
  auto what = [](VkResult r) {
    try {
      vk_check(r, "vkAllocateMemory");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(what(VK_ERROR_OUT_OF_DEVICE_MEMORY).find("(VK_ERROR_OUT_OF_DEVICE_MEMORY -2): out of memory"),
            std::string::npos);
  EXPECT_NE(what(VK_ERROR_OUT_OF_HOST_MEMORY).find(": out of memory"), std::string::npos);
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &old), 0);
  rlimit finite = old;
  finite.rlim_cur = old.rlim_max == RLIM_INFINITY ? RLIM_INFINITY - 1 : old.rlim_max;
  if (finite.rlim_cur == RLIM_INFINITY || setrlimit(RLIMIT_AS, &finite) != 0) GTEST_SKIP() << "no finite limit to set";
  const std::string device = what(VK_ERROR_OUT_OF_DEVICE_MEMORY), host = what(VK_ERROR_OUT_OF_HOST_MEMORY),
                    unknown = what(VK_ERROR_UNKNOWN), lost = what(VK_ERROR_DEVICE_LOST);
  ASSERT_EQ(setrlimit(RLIMIT_AS, &old), 0);
  EXPECT_NE(device.find(": out of memory"), std::string::npos) << device;
  EXPECT_EQ(device.find("ulimit"), std::string::npos) << device;
  EXPECT_NE(host.find(": out of memory; the address-space limit (ulimit -v "), std::string::npos) << host;
  EXPECT_NE(unknown.find("the address-space limit (ulimit -v "), std::string::npos) << unknown;
  EXPECT_EQ(lost.find("ulimit"), std::string::npos) << lost;
}

TEST_F(DeviceTest, BadDeviceIndexIsAUserError) {
  VulkanOptions options;
  options.device_index = 1000;
  EXPECT_THROW(VulkanContext::create(options), Error);
}

// The layer reports a bad call it sees before any messenger exists (creating the messenger
// itself) on stdout, where no count sees it: --vk-validate exited 0 with such an error
// (vkCreateDebugUtilsMessengerEXT got the instance's validation features in its chain).
TEST_F(DeviceTest, ValidatedSetUpPrintsNothing) {
  VulkanOptions options;
  options.validate = true;
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  {
    const std::unique_ptr<VulkanContext> validated = VulkanContext::create(options);
    EXPECT_TRUE(validated->validation_enabled());
    EXPECT_EQ(validated->validation_message_count(), 0);
  }
  const std::string out = testing::internal::GetCapturedStdout(), err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
}

TEST_F(DeviceTest, FindsNoDeviceGracefully) {
  // An ICD list naming a missing driver leaves the loader without devices: a clear
  // zz::Error, never a crash. (The loader reads the variable at instance creation.)
  const char* saved = std::getenv("VK_DRIVER_FILES");
  std::string keep = saved ? saved : "";
  setenv("VK_DRIVER_FILES", "/nonexistent/zz_icd.json", 1);
  try {
    VulkanContext::create({});
    ADD_FAILURE() << "expected zz::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mesa-vulkan-drivers"), std::string::npos) << e.what();
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur == RLIM_INFINITY) {
      EXPECT_EQ(std::string(e.what()).find("ulimit"), std::string::npos) << e.what();
    }
  }
  // Under an address-space limit (here one too large to bind) a driver may fail to start:
  // the message says so beside the install hint, which alone sent users with lavapipe
  // installed to install it again.
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &old), 0);
  rlimit finite = old;
  finite.rlim_cur = old.rlim_max == RLIM_INFINITY ? RLIM_INFINITY - 1 : old.rlim_max;
  if (finite.rlim_cur != RLIM_INFINITY && setrlimit(RLIMIT_AS, &finite) == 0) {
    try {
      VulkanContext::create({});
      ADD_FAILURE() << "expected zz::Error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("the address-space limit (ulimit -v "), std::string::npos) << e.what();
    }
    EXPECT_EQ(setrlimit(RLIMIT_AS, &old), 0);
  }
  if (saved) setenv("VK_DRIVER_FILES", keep.c_str(), 1);
  else unsetenv("VK_DRIVER_FILES");
}

}  // namespace
}  // namespace zz::test
