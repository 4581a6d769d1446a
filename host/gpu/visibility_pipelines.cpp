// The visibility pass's pipelines: the id raster (dynamic rendering, reverse-Z), the
// per-frame triangle planes and the flag compute shader (one per S) with their descriptor set.
#include "core/error.h"
#include "gpu/shaders.h"
#include "gpu/visibility.h"

namespace zz {

namespace {

// Shader modules destroyed however the function that made them returns (null handles are
// ignored): a pipeline keeps what it needs of them.
template <size_t N>
struct ShaderModules {
  VkDevice d;
  VkShaderModule m[N] = {};
  ~ShaderModules() {
    for (VkShaderModule x : m) vkDestroyShaderModule(d, x, nullptr);
  }
};

}  // namespace

void VisibilityPass::create_pipelines() {
  VkDevice d = context_.device();
  ShaderModules<1> modules{d};
  const VkShaderModule planes = modules.m[0] = create_shader_module(d, shader_triangle_planes_comp());
  flag_module_ = create_shader_module(d, shader_geo_flags_comp());  // specialised per S later

  // Raster: positions in, triangle id out, reverse-Z depth (GREATER, clear 0).
  VkPushConstantRange raster_push{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(gpu::RasterPush)};
  VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout.pushConstantRangeCount = 1;
  layout.pPushConstantRanges = &raster_push;
  vk_check(vkCreatePipelineLayout(d, &layout, nullptr, &raster_layout_), "vkCreatePipelineLayout");

  raster_pipeline_ = make_raster_pipeline(shader_ids_vert());

  // Compute: ids (storage image), first vertices, normals, planes, packed flags; one set and
  // one layout for the planes pass and the flag pass.
  VkDescriptorSetLayoutBinding bindings[5] = {
      {ZZ_BIND_IDS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {ZZ_BIND_FIRST_VERTICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {ZZ_BIND_NORMALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {ZZ_BIND_PLANES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {ZZ_BIND_FLAGS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
  VkDescriptorSetLayoutCreateInfo set_layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_layout.bindingCount = 5;
  set_layout.pBindings = bindings;
  vk_check(vkCreateDescriptorSetLayout(d, &set_layout, nullptr, &flag_set_layout_),
           "vkCreateDescriptorSetLayout");
  VkPushConstantRange flag_push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::FlagPush)};
  VkPipelineLayoutCreateInfo flag_layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  flag_layout.setLayoutCount = 1;
  flag_layout.pSetLayouts = &flag_set_layout_;
  flag_layout.pushConstantRangeCount = 1;
  flag_layout.pPushConstantRanges = &flag_push;
  vk_check(vkCreatePipelineLayout(d, &flag_layout, nullptr, &flag_layout_), "vkCreatePipelineLayout");
  VkComputePipelineCreateInfo compute{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  compute.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  compute.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  compute.stage.module = planes;
  compute.stage.pName = "main";
  compute.layout = flag_layout_;
  vk_check(vkCreateComputePipelines(d, VK_NULL_HANDLE, 1, &compute, nullptr, &plane_pipeline_),
           "vkCreateComputePipelines");

  VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1}, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 4}};
  VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool.maxSets = 1;
  pool.poolSizeCount = 2;
  pool.pPoolSizes = sizes;
  vk_check(vkCreateDescriptorPool(d, &pool, nullptr, &descriptor_pool_), "vkCreateDescriptorPool");
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = descriptor_pool_;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &flag_set_layout_;
  vk_check(vkAllocateDescriptorSets(d, &alloc, &flag_set_), "vkAllocateDescriptorSets");
}

VkPipeline VisibilityPass::flag_pipeline(int s, bool orthographic) {
  auto found = flag_pipelines_.find({s, orthographic});
  if (found != flag_pipelines_.end()) return found->second;
  const int32_t constants[2] = {s, orthographic ? 1 : 0};  // S, ORTHOGRAPHIC (a 32-bit bool)
  const VkSpecializationMapEntry entries[2] = {{0, 0, sizeof(int32_t)}, {1, sizeof(int32_t), sizeof(int32_t)}};
  VkSpecializationInfo specialization{2, entries, sizeof(constants), constants};
  VkComputePipelineCreateInfo compute{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  compute.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  compute.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  compute.stage.module = flag_module_;
  compute.stage.pName = "main";
  compute.stage.pSpecializationInfo = &specialization;
  compute.layout = flag_layout_;
  VkPipeline pipeline = VK_NULL_HANDLE;
  vk_check(vkCreateComputePipelines(context_.device(), VK_NULL_HANDLE, 1, &compute, nullptr, &pipeline),
           "vkCreateComputePipelines");
  flag_pipelines_[{s, orthographic}] = pipeline;
  return pipeline;
}

VkPipeline VisibilityPass::make_raster_pipeline(ShaderCode vertex_shader) {
  VkDevice d = context_.device();
  ShaderModules<2> modules{d};
  const VkShaderModule vert = modules.m[0] = create_shader_module(d, vertex_shader);
  const VkShaderModule frag = modules.m[1] = create_shader_module(d, shader_ids_frag());
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vert;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = frag;
  stages[1].pName = "main";

  VkVertexInputBindingDescription binding{0, sizeof(glm::vec4), VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription attribute{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0};
  VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertex_input.vertexBindingDescriptionCount = 1;
  vertex_input.pVertexBindingDescriptions = &binding;
  vertex_input.vertexAttributeDescriptionCount = 1;
  vertex_input.pVertexAttributeDescriptions = &attribute;
  VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = VK_CULL_MODE_NONE;  // the ray tracer sees both sides
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = VK_TRUE;
  depth.depthCompareOp = VK_COMPARE_OP_GREATER;
  VkPipelineColorBlendAttachmentState blend_attachment{};
  blend_attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT;
  VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = 1;
  blend.pAttachments = &blend_attachment;
  VkDynamicState dynamic_states[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = 1;
  rendering.pColorAttachmentFormats = &kIdFormat;
  rendering.depthAttachmentFormat = kDepthFormat;

  VkGraphicsPipelineCreateInfo graphics{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  graphics.pNext = &rendering;
  graphics.stageCount = 2;
  graphics.pStages = stages;
  graphics.pVertexInputState = &vertex_input;
  graphics.pInputAssemblyState = &assembly;
  graphics.pViewportState = &viewport;
  graphics.pRasterizationState = &raster;
  graphics.pMultisampleState = &multisample;
  graphics.pDepthStencilState = &depth;
  graphics.pColorBlendState = &blend;
  graphics.pDynamicState = &dynamic;
  graphics.layout = raster_layout_;
  VkPipeline pipeline = VK_NULL_HANDLE;
  vk_check(vkCreateGraphicsPipelines(d, VK_NULL_HANDLE, 1, &graphics, nullptr, &pipeline), "vkCreateGraphicsPipelines");
  return pipeline;
}

VkPipeline VisibilityPass::raster_clip_pipeline() {
  if (raster_clip_pipeline_) return raster_clip_pipeline_;
  if (!context_.clip_distance()) throw Error("internal: the clipping raster asked of a device without shaderClipDistance");
  raster_clip_pipeline_ = make_raster_pipeline(shader_ids_clip_vert());
  return raster_clip_pipeline_;
}


}  // namespace zz
