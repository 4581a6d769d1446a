// volk's function pointers and loader (Debian's libvulkan-volk-dev ships it as source):
// zigzag does not link libvulkan, so it starts, and renders with --edges off, on a machine
// without the Vulkan loader; VulkanContext says what to install when a map is asked for.
#define VOLK_IMPLEMENTATION
#include <volk.h>
