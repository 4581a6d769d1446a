#include <gtest/gtest.h>

#include "gpu/resources.h"
#include "gpu_fixture.h"

namespace zz::test {
namespace {

using DeviceTest = GpuTest;

TEST_F(DeviceTest, CreatesDeviceWithGraphicsComputeQueue) {
  EXPECT_FALSE(context().device_name().empty());
  EXPECT_NE(context().device(), VK_NULL_HANDLE);
  EXPECT_NE(context().queue(), VK_NULL_HANDLE);
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

TEST_F(DeviceTest, BadDeviceIndexIsAUserError) {
  VulkanOptions options;
  options.device_index = 1000;
  EXPECT_THROW(VulkanContext::create(options), Error);
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
  }
  if (saved) setenv("VK_DRIVER_FILES", keep.c_str(), 1);
  else unsetenv("VK_DRIVER_FILES");
}

}  // namespace
}  // namespace zz::test
