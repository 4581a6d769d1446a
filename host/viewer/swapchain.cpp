#include "viewer/swapchain.h"

#include <algorithm>

#include "core/error.h"
#include "gpu/device.h"

namespace zz {

VkSurfaceFormatKHR choose_surface_format(const std::vector<VkSurfaceFormatKHR>& formats) {
  if (formats.empty()) throw Error("Vulkan: the window surface offers no formats");
  // VK_FORMAT_UNDEFINED alone means "any format" (old drivers).
  if (formats.size() == 1 && formats[0].format == VK_FORMAT_UNDEFINED)
    return {VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
  // The presenter copies display-encoded 8-bit bytes: UNORM shows them as they are, and an
  // SRGB format takes them as already encoded (a copy converts nothing). Anything else (a
  // 10-bit packed format) would scramble them.
  for (VkFormat want : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                        VK_FORMAT_R8G8B8A8_SRGB})
    for (const VkSurfaceFormatKHR& f : formats)
      if (f.format == want) return f;
  throw Error("Vulkan: the window offers no 8-bit RGBA format (first offered: format " +
              std::to_string(int(formats[0].format)) + "); use `zigzag render`");
}

bool create_swapchain(VulkanContext& context, Swapchain& sc, uint32_t width, uint32_t height) {
  VkPhysicalDevice physical = context.physical_device();
  VkSurfaceKHR surface = context.surface();
  VkSurfaceCapabilitiesKHR caps;
  vk_check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface, &caps),
           "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  uint32_t count = 0;
  vk_check(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, nullptr),
           "vkGetPhysicalDeviceSurfaceFormatsKHR");
  std::vector<VkSurfaceFormatKHR> formats(count);
  vk_check(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, formats.data()),
           "vkGetPhysicalDeviceSurfaceFormatsKHR");
  const VkSurfaceFormatKHR format = choose_surface_format(formats);
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
    throw Error("Vulkan: swapchain images cannot be transfer destinations on this device");

  // currentExtent 0xFFFFFFFF: the surface takes the swapchain's size.
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == 0xFFFFFFFFu) {
    extent.width = std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  if (extent.width == 0 || extent.height == 0) return false;

  uint32_t images = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount > 0) images = std::min(images, caps.maxImageCount);
  const VkCompositeAlphaFlagBitsKHR alpha =
      (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR) ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
      : (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR) ? VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR
                                                                             : VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR;

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface;
  info.minImageCount = images;
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                          ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                          : caps.currentTransform;
  info.compositeAlpha = alpha;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // the one mode every implementation must offer
  info.clipped = VK_TRUE;
  info.oldSwapchain = sc.swapchain;

  VkSwapchainKHR created = VK_NULL_HANDLE;
  vk_check(vkCreateSwapchainKHR(context.device(), &info, nullptr, &created), "vkCreateSwapchainKHR");
  // The old swapchain's images may still be in use by the presentation engine: the
  // caller waited for the device to be idle before recreating.
  if (sc.swapchain) vkDestroySwapchainKHR(context.device(), sc.swapchain, nullptr);
  sc.swapchain = created;
  sc.format = format.format;
  sc.extent = extent;
  sc.bgra = format.format != VK_FORMAT_R8G8B8A8_UNORM && format.format != VK_FORMAT_R8G8B8A8_SRGB;
  vk_check(vkGetSwapchainImagesKHR(context.device(), created, &count, nullptr), "vkGetSwapchainImagesKHR");
  sc.images.resize(count);
  vk_check(vkGetSwapchainImagesKHR(context.device(), created, &count, sc.images.data()), "vkGetSwapchainImagesKHR");
  return true;
}

void destroy_swapchain(VulkanContext& context, Swapchain& sc) {
  if (sc.swapchain) vkDestroySwapchainKHR(context.device(), sc.swapchain, nullptr);
  sc = Swapchain();
}

}  // namespace zz
