#include "gpu/device.h"

#include <cstdio>
#include <cstring>
#include <mutex>

#include "core/address_space.h"
#include "core/error.h"

namespace zz {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
// The remedies: a driver to install, then what the user may do without one (the options'
// without_vulkan, when there is anything).
std::string or_without_vulkan(const VulkanOptions& o) {
  return o.without_vulkan.empty() ? "" : " or " + o.without_vulkan;
}

// "ulimit -v N" when the process has an address-space limit, else "": lavapipe that cannot
// map its memory under one lists no device or fails to create it (VK_ERROR_UNKNOWN), and
// the install hint alone sent users with the driver installed to reinstall it.
std::string ulimit_v() {
  const uint64_t limit = address_space_limit();
  return limit == 0 ? "" : "ulimit -v " + std::to_string(limit / 1024);
}

std::string no_device(const VulkanOptions& o) {
  std::string why = "no Vulkan device found; install one with `apt-get install mesa-vulkan-drivers` (lavapipe, CPU)" +
                    or_without_vulkan(o);
  if (const std::string limit = ulimit_v(); !limit.empty())
    why += "; with the driver installed, the address-space limit (" + limit + ") may be too small for it";
  return why;
}

std::string no_loader(const VulkanOptions& o) {
  return "the Vulkan loader (libvulkan.so.1) could not be opened; install it and a driver with "
         "`apt-get install libvulkan1 mesa-vulkan-drivers` (lavapipe, CPU)" +
         or_without_vulkan(o);
}

// volk's function pointers are process-wide: libvulkan is opened once, and each new
// instance reloads them under this lock. The loader's core entry points are trampolines
// that dispatch on the handle, the same for every instance, but an instance extension's
// (VK_KHR_surface) is null for an instance that did not enable it: a headless context
// made while a windowed one lives would blank the latter's. zigzag makes one context per
// process (render, view); the tests' extra ones are headless and use no surface.
std::mutex volk_lock;

void load_vulkan(const VulkanOptions& options) {
  static std::once_flag once;
  static VkResult loaded = VK_ERROR_INITIALIZATION_FAILED;
  std::call_once(once, [] { loaded = volkInitialize(); });
  if (loaded != VK_SUCCESS) throw Error(no_loader(options));
}

bool has_layer(const char* name) {
  uint32_t count = 0;
  if (vkEnumerateInstanceLayerProperties(&count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

bool layer_has_extension(const char* layer, const char* extension) {
  uint32_t count = 0;
  if (vkEnumerateInstanceExtensionProperties(layer, &count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateInstanceExtensionProperties(layer, &count, extensions.data());
  for (const auto& e : extensions)
    if (std::strcmp(e.extensionName, extension) == 0) return true;
  return false;
}

// Lower rank = preferred: real GPUs first, lavapipe (CPU) last.
int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

// A queue family with graphics + compute (+ present to `surface`), or -1.
int find_queue_family(VkPhysicalDevice device, VkSurfaceKHR surface) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  for (uint32_t i = 0; i < count; ++i) {
    VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & need) != need) continue;
    if (surface != VK_NULL_HANDLE) {
      VkBool32 present = VK_FALSE;
      if (vkGetPhysicalDeviceSurfaceSupportKHR(device, i, surface, &present) != VK_SUCCESS || !present)
        continue;
    }
    return int(i);
  }
  return -1;
}

}  // namespace

const char* vk_result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_UNKNOWN: return "VK_ERROR_UNKNOWN";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_ERROR_INVALID_EXTERNAL_HANDLE: return "VK_ERROR_INVALID_EXTERNAL_HANDLE";
    case VK_ERROR_FRAGMENTATION: return "VK_ERROR_FRAGMENTATION";
    case VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS: return "VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS";
    case VK_ERROR_SURFACE_LOST_KHR: return "VK_ERROR_SURFACE_LOST_KHR";
    case VK_ERROR_NATIVE_WINDOW_IN_USE_KHR: return "VK_ERROR_NATIVE_WINDOW_IN_USE_KHR";
    case VK_SUBOPTIMAL_KHR: return "VK_SUBOPTIMAL_KHR";
    case VK_ERROR_OUT_OF_DATE_KHR: return "VK_ERROR_OUT_OF_DATE_KHR";
    default: return "VkResult error";
  }
}

void vk_check(VkResult result, const char* what) {
  if (result == VK_SUCCESS) return;
  std::string why = std::string("Vulkan: ") + what + " failed (" + vk_result_name(result) + " " +
                    std::to_string(int(result)) + ")";
  if (result == VK_ERROR_OUT_OF_HOST_MEMORY || result == VK_ERROR_OUT_OF_DEVICE_MEMORY) why += ": out of memory";
  // A GPU's own memory is no address space of ours: the hint is for the driver's host side.
  if (const std::string limit = ulimit_v();
      !limit.empty() && (result == VK_ERROR_OUT_OF_HOST_MEMORY || result == VK_ERROR_UNKNOWN ||
                         result == VK_ERROR_INITIALIZATION_FAILED))
    why += "; the address-space limit (" + limit + ") may be too small for the Vulkan driver";
  throw Error(why);
}

std::unique_ptr<VulkanContext> VulkanContext::create(const VulkanOptions& options) {
  std::unique_ptr<VulkanContext> context(new VulkanContext);
  context->init(options);  // on a throw the destructor releases what was made
  return context;
}

void VulkanContext::init(const VulkanOptions& options) {
  quiet_ = options.quiet;
  create_instance(options);
  if (options.create_surface) surface_ = options.create_surface(instance_);
  pick_device(options);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  features13.dynamicRendering = VK_TRUE;
  features13.synchronization2 = VK_TRUE;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &features13;
  // Clip distances, for a camera whose znear/zfar cut into the scene (gpu/visibility.cpp).
  VkPhysicalDeviceFeatures supported{};
  vkGetPhysicalDeviceFeatures(physical_, &supported);
  clip_distance_ = supported.shaderClipDistance == VK_TRUE;
  features.features.shaderClipDistance = supported.shaderClipDistance;

  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue_info;
  info.enabledExtensionCount = uint32_t(options.device_extensions.size());
  info.ppEnabledExtensionNames = options.device_extensions.data();
  vk_check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = queue_family_;
  vk_check(vkCreateCommandPool(device_, &pool, nullptr, &command_pool_), "vkCreateCommandPool");
}

void VulkanContext::create_instance(const VulkanOptions& options) {
  load_vulkan(options);
  std::vector<const char*> layers;
  std::vector<const char*> extensions = options.instance_extensions;
  if (options.validate) {
    if (!has_layer(kValidationLayer))
      throw Error(std::string("Vulkan validation requested but ") + kValidationLayer +
                  " is missing; install it with `apt-get install vulkan-validationlayers`");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  // Synchronisation validation too: the default checks do not see a missing barrier.
  const bool sync_validation =
      options.validate && layer_has_extension(kValidationLayer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  if (sync_validation) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
  const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "zigzag";
  app.apiVersion = VK_API_VERSION_1_3;

  VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &VulkanContext::on_message;
  messenger.pUserData = this;
  if (sync_validation) messenger.pNext = &features;

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = options.validate ? &messenger : nullptr;  // also covers create/destroy
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkResult r = vkCreateInstance(&info, nullptr, &instance_);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED) throw Error(no_device(options));
  vk_check(r, "vkCreateInstance");
  {
    const std::lock_guard<std::mutex> lock(volk_lock);
    volkLoadInstance(instance_);  // instance and device entry points (load_vulkan)
  }

  if (options.validate) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw Error("Vulkan: vkCreateDebugUtilsMessengerEXT is unavailable");
    // The validation features belong to the instance's chain only: this call takes none,
    // and the layer's complaint about one came before any messenger could count it.
    messenger.pNext = nullptr;
    vk_check(create(instance_, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
}

void VulkanContext::pick_device(const VulkanOptions& options) {
  uint32_t count = 0;
  VkResult r = vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  if (r == VK_ERROR_INITIALIZATION_FAILED || count == 0) throw Error(no_device(options));
  vk_check(r, "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  vk_check(vkEnumeratePhysicalDevices(instance_, &count, devices.data()), "vkEnumeratePhysicalDevices");

  auto usable = [&](VkPhysicalDevice d, std::string* why) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    if (p.apiVersion < VK_API_VERSION_1_3) {
      if (why) *why = "it supports only Vulkan " + std::to_string(VK_API_VERSION_MAJOR(p.apiVersion)) + "." +
                      std::to_string(VK_API_VERSION_MINOR(p.apiVersion)) + " (1.3 needed)";
      return false;
    }
    if (find_queue_family(d, surface_) < 0) {
      if (why) *why = "it has no graphics+compute queue" + std::string(surface_ ? " that can present" : "");
      return false;
    }
    return true;
  };

  int chosen = -1;
  if (options.device_index >= 0) {
    if (options.device_index >= int(count))
      throw Error("Vulkan device " + std::to_string(options.device_index) + " does not exist (" +
                  std::to_string(count) + " found)");
    std::string why;
    if (!usable(devices[options.device_index], &why))
      throw Error("Vulkan device " + std::to_string(options.device_index) + " is unusable: " + why);
    chosen = options.device_index;
  } else {
    int best_rank = 1 << 30;
    std::string rejected;  // the devices present but unusable, and why
    for (uint32_t i = 0; i < count; ++i) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(devices[i], &p);
      std::string why;
      if (!usable(devices[i], &why)) {
        rejected += std::string(rejected.empty() ? "" : "; ") + "device " + std::to_string(i) + " (" +
                    p.deviceName + "): " + why;
      } else if (type_rank(p.deviceType) < best_rank) {
        best_rank = type_rank(p.deviceType);
        chosen = int(i);
      }
    }
    // Devices that exist but cannot run the map: say why, and that a newer driver is the
    // remedy; "install lavapipe" misled where an old one was installed.
    if (chosen < 0 && !rejected.empty())
      throw Error("no usable Vulkan device (" + rejected +
                  "); install a newer driver (Debian 12's mesa-vulkan-drivers gives a lavapipe with "
                  "Vulkan 1.3)" + or_without_vulkan(options));
    if (chosen < 0) throw Error(no_device(options));
  }

  physical_ = devices[chosen];
  vkGetPhysicalDeviceProperties(physical_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  queue_family_ = uint32_t(find_queue_family(physical_, surface_));
  uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &families, nullptr);
  std::vector<VkQueueFamilyProperties> props(families);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &families, props.data());
  timestamp_bits_ = properties_.limits.timestampComputeAndGraphics ? props[queue_family_].timestampValidBits : 0;
}

void VulkanContext::close() noexcept {
  if (device_) {
    wait_idle_noexcept();
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    command_pool_ = VK_NULL_HANDLE;
    device_ = VK_NULL_HANDLE;
  }
  if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
  surface_ = VK_NULL_HANDLE;
}

VulkanContext::~VulkanContext() {
  close();
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                         void* user) {
  auto* self = static_cast<VulkanContext*>(user);
  self->messages_.fetch_add(1);
  if (!self->quiet_) {
    const char* level = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning";
    std::fprintf(stderr, "vulkan validation %s: %s\n", level, data && data->pMessage ? data->pMessage : "");
  }
  return VK_FALSE;
}

uint32_t VulkanContext::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                                    VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    VkMemoryPropertyFlags f = memory_.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    if ((f & preferred) == preferred) return i;
    if (fallback < 0) fallback = int(i);
  }
  if (fallback < 0) throw Error("Vulkan: no suitable memory type");
  return uint32_t(fallback);
}

VkMemoryPropertyFlags VulkanContext::memory_flags(uint32_t type) const {
  return memory_.memoryTypes[type].propertyFlags;
}

void VulkanContext::submit(const VkSubmitInfo& submit, VkFence fence) {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  vk_check(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit");
}

VkResult VulkanContext::present(const VkPresentInfoKHR& info) {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  return vkQueuePresentKHR(queue_, &info);
}

void VulkanContext::wait_idle() {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  vk_check(vkDeviceWaitIdle(device_), "vkDeviceWaitIdle");
}

void VulkanContext::wait_idle_noexcept() noexcept {
  try {
    wait_idle();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "zigzag: %s\n", e.what());
  }
}

void VulkanContext::run_commands(const std::function<void(VkCommandBuffer)>& record) {
  // A command buffer's pool stays externally synchronised while it is recorded or
  // freed, so recording holds the pool lock; the GPU wait holds neither lock.
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  auto free_commands = [&] {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    vkFreeCommandBuffers(device_, command_pool_, 1, &cmd);
  };
  {
    std::lock_guard<std::mutex> lock(pool_mutex_);
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = command_pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    vk_check(vkAllocateCommandBuffers(device_, &alloc, &cmd), "vkAllocateCommandBuffers");
    try {
      VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
      begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
      vk_check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
      record(cmd);
      vk_check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    } catch (...) {
      vkFreeCommandBuffers(device_, command_pool_, 1, &cmd);  // never submitted
      throw;
    }
  }
  VkFence fence = VK_NULL_HANDLE;
  try {
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    vk_check(vkCreateFence(device_, &fence_info, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo info{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    info.commandBufferCount = 1;
    info.pCommandBuffers = &cmd;
    submit(info, fence);
    vk_check(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  } catch (...) {
    wait_idle_noexcept();  // the buffer may still be pending: it cannot be freed before
    if (fence) vkDestroyFence(device_, fence, nullptr);
    free_commands();
    throw;
  }
  vkDestroyFence(device_, fence, nullptr);
  free_commands();
}

}  // namespace zz
