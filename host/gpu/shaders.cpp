#include "gpu/shaders.h"

#include "gpu/device.h"
#include "shaders/geo_flags.comp.spv.h"
#include "shaders/ids.frag.spv.h"
#include "shaders/ids.vert.spv.h"
#include "shaders/ids_clip.vert.spv.h"
#include "shaders/triangle_planes.comp.spv.h"

namespace zz {

ShaderCode shader_ids_vert() { return {zz_spv_ids_vert, sizeof(zz_spv_ids_vert)}; }
ShaderCode shader_ids_clip_vert() { return {zz_spv_ids_clip_vert, sizeof(zz_spv_ids_clip_vert)}; }
ShaderCode shader_ids_frag() { return {zz_spv_ids_frag, sizeof(zz_spv_ids_frag)}; }
ShaderCode shader_geo_flags_comp() { return {zz_spv_geo_flags_comp, sizeof(zz_spv_geo_flags_comp)}; }
ShaderCode shader_triangle_planes_comp() {
  return {zz_spv_triangle_planes_comp, sizeof(zz_spv_triangle_planes_comp)};
}

VkShaderModule create_shader_module(VkDevice device, ShaderCode code) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = code.bytes;
  info.pCode = code.words;
  VkShaderModule module = VK_NULL_HANDLE;
  vk_check(vkCreateShaderModule(device, &info, nullptr, &module), "vkCreateShaderModule");
  return module;
}

}  // namespace zz
