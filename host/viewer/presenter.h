// Puts the DisplayFrame on screen: the composed view is copied into a host-visible
// staging buffer and from there into the acquired swapchain image with
// vkCmdCopyBufferToImage — no graphics pipeline. One frame in flight: the viewer presents
// only when the picture changed, so there is nothing to overlap.
#pragma once

#include <volk.h>

#include <cstdint>
#include <vector>

#include "gpu/resources.h"
#include "viewer/display_frame.h"
#include "viewer/swapchain.h"

namespace zz {

class VulkanContext;

class Presenter {
 public:
  // The render thread may use the same context (the visibility pass): the presenter
  // records into its own command pool and submits/presents through the context's lock.
  explicit Presenter(VulkanContext& context);
  ~Presenter();
  Presenter(const Presenter&) = delete;
  Presenter& operator=(const Presenter&) = delete;

  // Presents `mode` of `frame` in a framebuffer of fb_width x fb_height (the swapchain
  // follows that size). Returns false when nothing could be shown (minimised window or
  // an out-of-date swapchain, which is recreated for the next call).
  bool present(const DisplayFrame& frame, ViewMode mode, uint32_t fb_width, uint32_t fb_height);

 private:
  bool ensure_swapchain(uint32_t fb_width, uint32_t fb_height);

  VulkanContext& context_;
  Swapchain swapchain_;
  bool out_of_date_ = false;
  VkCommandPool pool_ = VK_NULL_HANDLE;  // used on the UI thread only
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkSemaphore acquired_ = VK_NULL_HANDLE;
  std::vector<VkSemaphore> rendered_;  // one per swapchain image: reused only once that image is back
  Buffer staging_;
  std::vector<uint8_t> composed_;
};

}  // namespace zz
