// Buffers and images with their memory: plain move-only structs that free themselves.
#pragma once

#include <volk.h>

#include <cstddef>

namespace zz {

class VulkanContext;

struct Buffer {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  // persistently mapped when the memory is host-visible
  bool coherent = false;

  Buffer() = default;
  Buffer(Buffer&& other) noexcept { *this = static_cast<Buffer&&>(other); }
  Buffer& operator=(Buffer&& other) noexcept;
  ~Buffer() { reset(); }
  void reset();
};

struct Image {
  VkDevice device = VK_NULL_HANDLE;
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  uint32_t width = 0;
  uint32_t height = 0;

  Image() = default;
  Image(Image&& other) noexcept { *this = static_cast<Image&&>(other); }
  Image& operator=(Image&& other) noexcept;
  ~Image() { reset(); }
  void reset();
};

// `required` memory flags must hold; `preferred` ones are taken when some type has them.
Buffer create_buffer(VulkanContext& context, VkDeviceSize size, VkBufferUsageFlags usage,
                     VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred = 0);
// Writes `bytes` at offset 0: directly when mapped, else through a staging copy
// (`buffer` then needs TRANSFER_DST usage).
void upload(VulkanContext& context, Buffer& buffer, const void* data, size_t bytes);
// Makes device writes visible to the host for non-coherent memory.
void invalidate(const Buffer& buffer);

// One global memory dependency (synchronization2): writes of `src` visible to `dst`.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

Image create_image_2d(VulkanContext& context, uint32_t width, uint32_t height, VkFormat format,
                      VkImageUsageFlags usage, VkImageAspectFlags aspect);

}  // namespace zz
