#include "viewer/swapchain.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace zz {
namespace {

TEST(Swapchain, PrefersUnormBgraSoBytesPassUnchangedAndRefusesOtherLayouts) {
  const VkColorSpaceKHR srgb = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  // Lavapipe under Xvfb lists the sRGB format first (TOOLCHAIN.md).
  EXPECT_EQ(choose_surface_format({{VK_FORMAT_B8G8R8A8_SRGB, srgb}, {VK_FORMAT_B8G8R8A8_UNORM, srgb}}).format,
            VK_FORMAT_B8G8R8A8_UNORM);
  EXPECT_EQ(choose_surface_format({{VK_FORMAT_R8G8B8A8_SRGB, srgb}, {VK_FORMAT_R8G8B8A8_UNORM, srgb}}).format,
            VK_FORMAT_R8G8B8A8_UNORM);
  // Without UNORM, an SRGB 8-bit format takes the encoded bytes as they are.
  EXPECT_EQ(choose_surface_format({{VK_FORMAT_A2B10G10R10_UNORM_PACK32, srgb}, {VK_FORMAT_B8G8R8A8_SRGB, srgb}}).format,
            VK_FORMAT_B8G8R8A8_SRGB);
  // A packed 10-bit format would scramble 8-bit bytes: refused, not used.
  EXPECT_THROW(choose_surface_format({{VK_FORMAT_A2B10G10R10_UNORM_PACK32, srgb}}), Error);
  EXPECT_EQ(choose_surface_format({{VK_FORMAT_UNDEFINED, srgb}}).format, VK_FORMAT_B8G8R8A8_UNORM);
  EXPECT_THROW(choose_surface_format({}), Error);
}

}  // namespace
}  // namespace zz
