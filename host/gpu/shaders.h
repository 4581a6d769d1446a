// SPIR-V compiled from shaders/*.{vert,frag,comp} at build time and linked into the binary.
#pragma once

#include <volk.h>

#include <cstddef>
#include <cstdint>

namespace zz {

struct ShaderCode {
  const uint32_t* words;
  size_t bytes;
};

ShaderCode shader_ids_vert();
ShaderCode shader_ids_clip_vert();  // ids.vert with ZZ_CLIP_PLANES
ShaderCode shader_ids_frag();
ShaderCode shader_geo_flags_comp();
ShaderCode shader_triangle_planes_comp();

VkShaderModule create_shader_module(VkDevice device, ShaderCode code);

}  // namespace zz
