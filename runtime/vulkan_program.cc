#include "runtime/vulkan_program.h"

#include <string>

namespace ellipsekit {

Status VulkanFailure(const char* what, VkResult r) {
  return {StatusCode::kInternal, std::string(what) + " failed: " + VkResultName(r)};
}

Status VulkanProgram::Create(VulkanContext* ctx, int num_bindings, std::uint32_t push_constant_bytes,
                             const Shader* shaders, int num_shaders) {
  if (ctx == nullptr || ctx_ != nullptr || num_bindings <= 0 || num_bindings > kMaxBindings)
    return {StatusCode::kInternal, "VulkanProgram::Create: bad arguments or called twice"};
  ctx_ = ctx;
  num_bindings_ = num_bindings;
  const VulkanFunctions& vk = ctx_->vk();
  VkDevice dev = ctx_->device();

  VkDescriptorSetLayoutBinding bindings[kMaxBindings];
  for (int b = 0; b < num_bindings; ++b) {
    bindings[b] = VkDescriptorSetLayoutBinding{};
    bindings[b].binding = static_cast<std::uint32_t>(b);
    bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[b].descriptorCount = 1;
    bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dslci{};
  dslci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  dslci.bindingCount = static_cast<std::uint32_t>(num_bindings);
  dslci.pBindings = bindings;
  VkResult r = vk.vkCreateDescriptorSetLayout(dev, &dslci, nullptr, &set_layout_);
  if (r != VK_SUCCESS) return VulkanFailure("vkCreateDescriptorSetLayout", r);

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &set_layout_;
  plci.pushConstantRangeCount = 1;
  plci.pPushConstantRanges = &range;
  r = vk.vkCreatePipelineLayout(dev, &plci, nullptr, &pipeline_layout_);
  if (r != VK_SUCCESS) return VulkanFailure("vkCreatePipelineLayout", r);

  pipelines_.assign(static_cast<std::size_t>(num_shaders), VK_NULL_HANDLE);
  for (int p = 0; p < num_shaders; ++p) {
    VkShaderModuleCreateInfo smci{};
    smci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    smci.codeSize = shaders[p].bytes;
    smci.pCode = shaders[p].code;
    VkShaderModule module;
    r = vk.vkCreateShaderModule(dev, &smci, nullptr, &module);
    if (r != VK_SUCCESS) return VulkanFailure("vkCreateShaderModule", r);
    VkSpecializationMapEntry entry{0, 0, sizeof(std::uint32_t)};
    VkSpecializationInfo spec{1, &entry, sizeof(std::uint32_t), &shaders[p].constant0};
    VkComputePipelineCreateInfo cpci{};
    cpci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    if (shaders[p].specialized) cpci.stage.pSpecializationInfo = &spec;  // ignored without constant_id 0
    cpci.layout = pipeline_layout_;
    r = vk.vkCreateComputePipelines(dev, ctx_->pipeline_cache(), 1, &cpci, nullptr, &pipelines_[p]);
    vk.vkDestroyShaderModule(dev, module, nullptr);
    if (r != VK_SUCCESS) return VulkanFailure("vkCreateComputePipelines", r);
  }

  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, static_cast<std::uint32_t>(num_bindings)};
  VkDescriptorPoolCreateInfo dpci{};
  dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  dpci.maxSets = 1;
  dpci.poolSizeCount = 1;
  dpci.pPoolSizes = &pool_size;
  r = vk.vkCreateDescriptorPool(dev, &dpci, nullptr, &descriptor_pool_);
  if (r != VK_SUCCESS) return VulkanFailure("vkCreateDescriptorPool", r);
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = descriptor_pool_;
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &set_layout_;
  r = vk.vkAllocateDescriptorSets(dev, &dsai, &set_);
  if (r != VK_SUCCESS) return VulkanFailure("vkAllocateDescriptorSets", r);

  VkCommandPoolCreateInfo cpi{};
  cpi.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  cpi.queueFamilyIndex = ctx_->queue_family();
  r = vk.vkCreateCommandPool(dev, &cpi, nullptr, &command_pool_);
  if (r != VK_SUCCESS) return VulkanFailure("vkCreateCommandPool", r);
  VkCommandBufferAllocateInfo cbai{};
  cbai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cbai.commandPool = command_pool_;
  cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cbai.commandBufferCount = 2;
  r = vk.vkAllocateCommandBuffers(dev, &cbai, cbs_);
  if (r != VK_SUCCESS) return VulkanFailure("vkAllocateCommandBuffers", r);

  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  r = vk.vkCreateFence(dev, &fci, nullptr, &fence_);
  if (r != VK_SUCCESS) return VulkanFailure("vkCreateFence", r);
  if (ctx_->timestamp_valid_bits() != 0) {
    VkQueryPoolCreateInfo qpci{};
    qpci.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpci.queryCount = kMaxTimestamps;
    r = vk.vkCreateQueryPool(dev, &qpci, nullptr, &query_pool_);
    if (r != VK_SUCCESS) return VulkanFailure("vkCreateQueryPool", r);
  }
  return Status::Ok();
}

VulkanProgram::~VulkanProgram() {
  if (ctx_ == nullptr) return;
  const VulkanFunctions& vk = ctx_->vk();
  VkDevice dev = ctx_->device();
  if (query_pool_ != VK_NULL_HANDLE) vk.vkDestroyQueryPool(dev, query_pool_, nullptr);
  if (fence_ != VK_NULL_HANDLE) vk.vkDestroyFence(dev, fence_, nullptr);
  if (command_pool_ != VK_NULL_HANDLE) vk.vkDestroyCommandPool(dev, command_pool_, nullptr);
  if (descriptor_pool_ != VK_NULL_HANDLE) vk.vkDestroyDescriptorPool(dev, descriptor_pool_, nullptr);
  for (VkPipeline p : pipelines_)
    if (p != VK_NULL_HANDLE) vk.vkDestroyPipeline(dev, p, nullptr);
  if (pipeline_layout_ != VK_NULL_HANDLE) vk.vkDestroyPipelineLayout(dev, pipeline_layout_, nullptr);
  if (set_layout_ != VK_NULL_HANDLE) vk.vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
}

void VulkanProgram::BindBuffers(const VulkanBuffer* buffers) {
  VkDescriptorBufferInfo infos[kMaxBindings];
  VkWriteDescriptorSet writes[kMaxBindings];
  for (int b = 0; b < num_bindings_; ++b) {
    infos[b] = VkDescriptorBufferInfo{buffers[b].buffer, 0, VK_WHOLE_SIZE};
    writes[b] = VkWriteDescriptorSet{};
    writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[b].dstSet = set_;
    writes[b].dstBinding = static_cast<std::uint32_t>(b);
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  ctx_->vk().vkUpdateDescriptorSets(ctx_->device(), static_cast<std::uint32_t>(num_bindings_), writes, 0, nullptr);
}

void VulkanProgram::Dispatch(VkCommandBuffer cb, int i, std::uint32_t push_bytes, const void* push, std::uint32_t gx,
                             std::uint32_t gy) {
  const VulkanFunctions& vk = ctx_->vk();
  vk.vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline(i));
  vk.vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_, 0, 1, &set_, 0, nullptr);
  vk.vkCmdPushConstants(cb, pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes, push);
  vk.vkCmdDispatch(cb, gx, gy, 1);
}

void VulkanProgram::Barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access,
                            VkPipelineStageFlags dst, VkAccessFlags dst_access) {
  VkMemoryBarrier mb{};
  mb.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  mb.srcAccessMask = src_access;
  mb.dstAccessMask = dst_access;
  ctx_->vk().vkCmdPipelineBarrier(cb, src, dst, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

Status VulkanProgram::SubmitAndWait(VkCommandBuffer cb) {
  const VulkanFunctions& vk = ctx_->vk();
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  VkResult r = vk.vkQueueSubmit(ctx_->queue(), 1, &si, fence_);
  if (r != VK_SUCCESS) return VulkanFailure("vkQueueSubmit", r);
  r = vk.vkWaitForFences(ctx_->device(), 1, &fence_, VK_TRUE, UINT64_MAX);
  vk.vkResetFences(ctx_->device(), 1, &fence_);
  if (r != VK_SUCCESS) return VulkanFailure("vkWaitForFences", r);
  return Status::Ok();
}

void VulkanProgram::StartTimestamps(VkCommandBuffer cb, int first, int count) {
  if (query_pool_ == VK_NULL_HANDLE) return;
  const VulkanFunctions& vk = ctx_->vk();
  vk.vkCmdResetQueryPool(cb, query_pool_, static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(count));
  vk.vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, query_pool_, static_cast<std::uint32_t>(first));
}

void VulkanProgram::Timestamp(VkCommandBuffer cb, int query) {
  if (query_pool_ == VK_NULL_HANDLE) return;
  ctx_->vk().vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, static_cast<std::uint32_t>(query));
}

void VulkanProgram::AddIntervalsMs(int first, int count, double* ms) {
  if (query_pool_ == VK_NULL_HANDLE || first < 0 || count < 1 || first + count >= kMaxTimestamps) return;
  std::uint64_t ts[kMaxTimestamps] = {};
  const auto n = static_cast<std::uint32_t>(count + 1);
  if (ctx_->vk().vkGetQueryPoolResults(ctx_->device(), query_pool_, static_cast<std::uint32_t>(first), n,
                                       n * sizeof(std::uint64_t), ts, sizeof(std::uint64_t),
                                       VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) != VK_SUCCESS)
    return;
  const std::uint64_t mask = ctx_->timestamp_valid_bits() >= 64 ? ~0ull : ((1ull << ctx_->timestamp_valid_bits()) - 1);
  for (int i = 0; i < count; ++i)
    ms[i] += static_cast<double>((ts[i + 1] - ts[i]) & mask) * ctx_->timestamp_period_ns() * 1e-6;
}

}  // namespace ellipsekit
