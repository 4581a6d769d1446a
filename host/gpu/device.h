// The Vulkan instance, physical device, logical device, one queue and a command pool:
// everything the visibility pass and the viewer's presenter run on. The queue and the
// pool need external synchronisation (Vulkan spec 3.6), so the context owns the locks:
// callers on any thread submit, present and wait only through it.
#pragma once

#include <volk.h>  // the Vulkan API, its functions loaded at run time (load_vulkan in device.cpp)

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace zz {

struct VulkanOptions {
  int device_index = -1;  // -1: first discrete GPU, else integrated, else any (lavapipe)
  bool validate = false;  // VK_LAYER_KHRONOS_validation + a counting debug messenger
  bool quiet = false;     // do not print validation messages (they are still counted)
  std::vector<const char*> instance_extensions;  // e.g. from glfwGetRequiredInstanceExtensions
  std::vector<const char*> device_extensions;    // e.g. VK_KHR_swapchain
  // Called once the instance exists; the returned surface is owned (destroyed) by the
  // context and the chosen queue family can present to it.
  std::function<VkSurfaceKHR(VkInstance)> create_surface;
  // What the user can do instead when there is no Vulkan, for the error's remedy ("" for
  // nothing: the viewer cannot present without it).
  std::string without_vulkan = "run with --edges off";
};

// Throws zz::Error on a failed Vulkan call, naming the call and the result.
void vk_check(VkResult result, const char* what);
const char* vk_result_name(VkResult result);

class VulkanContext {
 public:
  // Throws zz::Error, e.g. "no Vulkan device found; install one with ...".
  static std::unique_ptr<VulkanContext> create(const VulkanOptions& options = {});
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  bool clip_distance() const { return clip_distance_; }  // shaderClipDistance enabled
  uint32_t queue_family() const { return queue_family_; }
  VkSurfaceKHR surface() const { return surface_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  std::string device_name() const { return properties_.deviceName; }
  bool is_cpu() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  bool timestamps() const { return timestamp_bits_ != 0; }

  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Validation warnings + errors reported since creation (tests assert 0).
  int validation_message_count() const { return messages_.load(); }

  // A memory type among `type_bits` with all `required` flags, preferring `preferred`;
  // throws zz::Error if none.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                       VkMemoryPropertyFlags preferred = 0) const;
  VkMemoryPropertyFlags memory_flags(uint32_t type) const;

  // Records with `record` into a fresh primary command buffer from the context's pool,
  // submits and waits. Safe to call from several threads at once.
  void run_commands(const std::function<void(VkCommandBuffer)>& record);

  // The queue operations, serialised by the context's queue lock (any thread).
  void submit(const VkSubmitInfo& submit, VkFence fence);
  VkResult present(const VkPresentInfoKHR& info);  // the caller handles OUT_OF_DATE/SUBOPTIMAL
  void wait_idle();                                // vkDeviceWaitIdle: every queue is used
  // For destructors: waits, and on failure prints the reason instead of throwing.
  void wait_idle_noexcept() noexcept;

  // Destroys the device, its pool and the surface, keeping the instance and the validation
  // messenger: objects still alive on the device are reported at vkDestroyDevice, so a
  // validation_message_count() read after close() includes them. Everything made on the
  // device must be gone; nothing but the count may be used afterwards. The destructor
  // closes a context that is still open.
  void close() noexcept;

 private:
  VulkanContext() = default;
  void init(const VulkanOptions& options);
  void create_instance(const VulkanOptions& options);
  void pick_device(const VulkanOptions& options);
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT type,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  uint32_t timestamp_bits_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;  // only run_commands uses it, under pool_mutex_
  std::mutex queue_mutex_;
  std::mutex pool_mutex_;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  std::atomic<int> messages_{0};
  bool quiet_ = false;
  bool clip_distance_ = false;
};

}  // namespace zz
