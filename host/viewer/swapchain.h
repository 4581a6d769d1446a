// The window's swapchain: B8G8R8A8_UNORM when offered (exact bytes, no sRGB re-encode:
// the display image is already tone-mapped and sRGB-encoded), FIFO present mode (always
// available, no tearing), images usable as transfer destinations so presentation is a
// buffer-to-image copy. Recreated on resize and on VK_ERROR_OUT_OF_DATE_KHR.
#pragma once

#include <volk.h>

#include <vector>

namespace zz {

class VulkanContext;

struct Swapchain {
  VkSwapchainKHR swapchain = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{0, 0};
  std::vector<VkImage> images;
  bool bgra = true;  // byte order of the format (B,G,R,A) vs (R,G,B,A)
};

// Prefers B8G8R8A8_UNORM, then R8G8B8A8_UNORM, then the first format (exposed for tests).
VkSurfaceFormatKHR choose_surface_format(const std::vector<VkSurfaceFormatKHR>& formats);

// (Re)creates `swapchain` for a framebuffer of width x height; the old handle is retired
// (passed as oldSwapchain, then destroyed). Returns false when the surface has zero area
// (minimised window): nothing can be presented then.
bool create_swapchain(VulkanContext& context, Swapchain& swapchain, uint32_t width, uint32_t height);
void destroy_swapchain(VulkanContext& context, Swapchain& swapchain);

}  // namespace zz
