#include "viewer/presenter.h"

#include <algorithm>
#include <cstring>

#include "gpu/device.h"

namespace zz {

Presenter::Presenter(VulkanContext& context) : context_(context) {
  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = context.queue_family();
  vk_check(vkCreateCommandPool(context.device(), &pool, nullptr, &pool_), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  vk_check(vkAllocateCommandBuffers(context.device(), &alloc, &commands_), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  vk_check(vkCreateFence(context.device(), &fence, nullptr, &fence_), "vkCreateFence");
  VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  vk_check(vkCreateSemaphore(context.device(), &sem, nullptr, &acquired_), "vkCreateSemaphore");
}

Presenter::~Presenter() {
  VkDevice device = context_.device();
  context_.wait_idle_noexcept();
  for (VkSemaphore s : rendered_) vkDestroySemaphore(device, s, nullptr);
  vkDestroySemaphore(device, acquired_, nullptr);
  vkDestroyFence(device, fence_, nullptr);
  vkFreeCommandBuffers(device, pool_, 1, &commands_);
  vkDestroyCommandPool(device, pool_, nullptr);
  staging_.reset();
  destroy_swapchain(context_, swapchain_);
}

bool Presenter::ensure_swapchain(uint32_t fb_width, uint32_t fb_height) {
  if (fb_width == 0 || fb_height == 0) return false;
  const bool size_changed = swapchain_.extent.width != fb_width || swapchain_.extent.height != fb_height;
  if (swapchain_.swapchain && !size_changed && !out_of_date_) return true;
  context_.wait_idle();  // the old images may still be written by a copy
  if (!create_swapchain(context_, swapchain_, fb_width, fb_height)) return false;
  out_of_date_ = false;
  VkSemaphoreCreateInfo sem{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  while (rendered_.size() < swapchain_.images.size()) {
    VkSemaphore s;
    vk_check(vkCreateSemaphore(context_.device(), &sem, nullptr, &s), "vkCreateSemaphore");
    rendered_.push_back(s);
  }
  return true;
}

bool Presenter::present(const DisplayFrame& frame, ViewMode mode, uint32_t fb_width, uint32_t fb_height) {
  VkDevice device = context_.device();
  vk_check(vkWaitForFences(device, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  if (!ensure_swapchain(fb_width, fb_height)) return false;

  uint32_t index = 0;
  VkResult r = vkAcquireNextImageKHR(device, swapchain_.swapchain, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) {
    out_of_date_ = true;  // the semaphore was not signalled: nothing to undo
    return false;
  }
  if (r != VK_SUBOPTIMAL_KHR) vk_check(r, "vkAcquireNextImageKHR");
  if (r == VK_SUBOPTIMAL_KHR) out_of_date_ = true;  // still present this one: the semaphore is signalled

  int width = 0, height = 0;
  frame.compose(mode, swapchain_.bgra, composed_, width, height);
  const VkDeviceSize bytes = std::max<VkDeviceSize>(composed_.size(), 4);
  if (staging_.size < bytes)
    staging_ = create_buffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                             VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  if (!composed_.empty()) std::memcpy(staging_.mapped, composed_.data(), composed_.size());

  vk_check(vkResetFences(device, 1, &fence_), "vkResetFences");
  vk_check(vkResetCommandBuffer(commands_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk_check(vkBeginCommandBuffer(commands_, &begin), "vkBeginCommandBuffer");

  const VkImage image = swapchain_.images[index];
  const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  VkImageMemoryBarrier to_dst{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  to_dst.srcAccessMask = 0;
  to_dst.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_dst.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;  // the whole image is rewritten
  to_dst.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  to_dst.srcQueueFamilyIndex = to_dst.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_dst.image = image;
  to_dst.subresourceRange = range;
  // Source stage = the stage the acquire semaphore is waited at, so the transition
  // happens after the presentation engine released the image.
  vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &to_dst);

  const uint32_t copy_w = std::min(uint32_t(width), swapchain_.extent.width);
  const uint32_t copy_h = std::min(uint32_t(height), swapchain_.extent.height);
  if (copy_w < swapchain_.extent.width || copy_h < swapchain_.extent.height) {
    // The frame is smaller than the window (a resize the renderer has not caught up with).
    VkClearColorValue grey{};
    grey.float32[0] = grey.float32[1] = grey.float32[2] = 0.08f;
    grey.float32[3] = 1.0f;
    vkCmdClearColorImage(commands_, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &grey, 1, &range);
    if (copy_w > 0 && copy_h > 0) {
      VkMemoryBarrier order{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      order.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      order.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
      vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &order, 0,
                           nullptr, 0, nullptr);
    }
  }
  if (copy_w > 0 && copy_h > 0) {
    VkBufferImageCopy region{};
    region.bufferOffset = 0;
    region.bufferRowLength = uint32_t(width);
    region.bufferImageHeight = uint32_t(height);
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {copy_w, copy_h, 1};
    vkCmdCopyBufferToImage(commands_, staging_.buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  }

  VkImageMemoryBarrier to_present = to_dst;
  to_present.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_present.dstAccessMask = 0;
  to_present.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  to_present.newLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr,
                       0, nullptr, 1, &to_present);
  vk_check(vkEndCommandBuffer(commands_), "vkEndCommandBuffer");

  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &acquired_;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands_;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &rendered_[index];
  context_.submit(submit, fence_);

  VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  info.waitSemaphoreCount = 1;
  info.pWaitSemaphores = &rendered_[index];
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain_.swapchain;
  info.pImageIndices = &index;
  r = context_.present(info);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
    out_of_date_ = true;
    return r == VK_SUBOPTIMAL_KHR;
  }
  vk_check(r, "vkQueuePresentKHR");
  return true;
}

}  // namespace zz
