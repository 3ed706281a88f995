#include "runtime/vulkan_edge_stage.h"

#include <stdint.h>  // the generated SPIR-V headers use ::uint32_t

#include <algorithm>
#include <cstring>
#include <string>

#include "kernels/canny_thresholds.h"
#include "shaders/canny_thresholds.spv.h"
#include "shaders/edge_sign.spv.h"
#include "shaders/gaussian.spv.h"
#include "shaders/hysteresis.spv.h"
#include "shaders/nms.spv.h"
#include "shaders/sobel.spv.h"

namespace ellipsekit {

namespace {

enum Binding : int { kImage, kBlurred, kDx, kDy, kHist, kThresholds, kMasks, kFlags, kEdges };

constexpr std::uint32_t kGroup = 64;               // local_size_x of gaussian, sobel, nms, edge_sign
constexpr std::uint32_t kRowsPerInvocation = 8;    // kRows of gaussian.comp, sobel.comp, nms.comp
constexpr std::uint32_t kHistVec4PerGroup = 256 * 8;  // canny_thresholds.comp MODE 0: 8 pixels each
constexpr std::uint32_t kHysteresisGroup = 8;      // local_size_x of hysteresis.comp (one strip each)
constexpr std::uint32_t kMaxGroups = 65535;      // guaranteed maxComputeWorkGroupCount per axis

Status VkFail(const char* what, VkResult r) {
  return {StatusCode::kInternal, std::string(what) + " failed: " + VkResultName(r)};
}

std::uint32_t CeilDiv(std::uint64_t a, std::uint64_t b) { return static_cast<std::uint32_t>((a + b - 1) / b); }

}  // namespace

Status VulkanEdgeStage::Create(std::unique_ptr<VulkanEdgeStage>* out) {
  std::unique_ptr<VulkanEdgeStage> stage(new VulkanEdgeStage());
  Status st = VulkanContext::Create(&stage->ctx_);
  if (!st.ok()) return st;
  st = stage->Init();
  if (!st.ok()) return st;
  *out = std::move(stage);
  return Status::Ok();
}

Status VulkanEdgeStage::Init() {
  const VulkanFunctions& vk = ctx_->vk();
  VkDevice dev = ctx_->device();

  VkDescriptorSetLayoutBinding bindings[kNumBindings];
  for (int b = 0; b < kNumBindings; ++b) {
    bindings[b] = VkDescriptorSetLayoutBinding{};
    bindings[b].binding = static_cast<std::uint32_t>(b);
    bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[b].descriptorCount = 1;
    bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dslci{};
  dslci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  dslci.bindingCount = kNumBindings;
  dslci.pBindings = bindings;
  VkResult r = vk.vkCreateDescriptorSetLayout(dev, &dslci, nullptr, &set_layout_);
  if (r != VK_SUCCESS) return VkFail("vkCreateDescriptorSetLayout", r);

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushWords * sizeof(std::uint32_t)};
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &set_layout_;
  plci.pushConstantRangeCount = 1;
  plci.pPushConstantRanges = &range;
  r = vk.vkCreatePipelineLayout(dev, &plci, nullptr, &pipeline_layout_);
  if (r != VK_SUCCESS) return VkFail("vkCreatePipelineLayout", r);

  struct Source {
    const std::uint32_t* code;
    std::size_t bytes;
    std::uint32_t mode;  // constant_id 0: canny_thresholds.comp MODE, sobel.comp FROM_BLURRED
  };
  const Source sources[kNumPipelines] = {
      {kGaussianSpv, sizeof(kGaussianSpv), 0},         {kSobelSpv, sizeof(kSobelSpv), 1},
      {kSobelSpv, sizeof(kSobelSpv), 0},
      {kCannyThresholdsSpv, sizeof(kCannyThresholdsSpv), 0}, {kCannyThresholdsSpv, sizeof(kCannyThresholdsSpv), 1},
      {kNmsSpv, sizeof(kNmsSpv), 0},                   {kHysteresisSpv, sizeof(kHysteresisSpv), 0},
      {kEdgeSignSpv, sizeof(kEdgeSignSpv), 0}};
  for (int p = 0; p < kNumPipelines; ++p) {
    VkShaderModuleCreateInfo smci{};
    smci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    smci.codeSize = sources[p].bytes;
    smci.pCode = sources[p].code;
    VkShaderModule module;
    r = vk.vkCreateShaderModule(dev, &smci, nullptr, &module);
    if (r != VK_SUCCESS) return VkFail("vkCreateShaderModule", r);
    VkSpecializationMapEntry entry{0, 0, sizeof(std::uint32_t)};
    VkSpecializationInfo spec{1, &entry, sizeof(std::uint32_t), &sources[p].mode};
    VkComputePipelineCreateInfo cpci{};
    cpci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = module;
    cpci.stage.pName = "main";
    cpci.stage.pSpecializationInfo = &spec;  // ignored by shaders without constant_id 0
    cpci.layout = pipeline_layout_;
    r = vk.vkCreateComputePipelines(dev, ctx_->pipeline_cache(), 1, &cpci, nullptr, &pipelines_[p]);
    vk.vkDestroyShaderModule(dev, module, nullptr);
    if (r != VK_SUCCESS) return VkFail("vkCreateComputePipelines", r);
  }

  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kNumBindings};
  VkDescriptorPoolCreateInfo dpci{};
  dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  dpci.maxSets = 1;
  dpci.poolSizeCount = 1;
  dpci.pPoolSizes = &pool_size;
  r = vk.vkCreateDescriptorPool(dev, &dpci, nullptr, &descriptor_pool_);
  if (r != VK_SUCCESS) return VkFail("vkCreateDescriptorPool", r);
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = descriptor_pool_;
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &set_layout_;
  r = vk.vkAllocateDescriptorSets(dev, &dsai, &set_);
  if (r != VK_SUCCESS) return VkFail("vkAllocateDescriptorSets", r);

  VkCommandPoolCreateInfo cpi{};

  cpi.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  cpi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  cpi.queueFamilyIndex = ctx_->queue_family();
  r = vk.vkCreateCommandPool(dev, &cpi, nullptr, &command_pool_);
  if (r != VK_SUCCESS) return VkFail("vkCreateCommandPool", r);
  VkCommandBufferAllocateInfo cbai{};
  cbai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cbai.commandPool = command_pool_;
  cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cbai.commandBufferCount = 2;
  VkCommandBuffer cbs[2];
  r = vk.vkAllocateCommandBuffers(dev, &cbai, cbs);
  if (r != VK_SUCCESS) return VkFail("vkAllocateCommandBuffers", r);
  frame_cb_ = cbs[0];
  more_rounds_cb_ = cbs[1];

  VkFenceCreateInfo fci{};

  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  r = vk.vkCreateFence(dev, &fci, nullptr, &fence_);
  if (r != VK_SUCCESS) return VkFail("vkCreateFence", r);
  if (ctx_->timestamp_valid_bits() != 0) {
    VkQueryPoolCreateInfo qpci{};
    qpci.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpci.queryCount = 2;
    r = vk.vkCreateQueryPool(dev, &qpci, nullptr, &query_pool_);
    if (r != VK_SUCCESS) return VkFail("vkCreateQueryPool", r);
  }
  return Status::Ok();
}

void VulkanEdgeStage::ReleaseFrameBuffers() {
  for (VulkanBuffer& b : buffers_) ctx_->DestroyBuffer(&b);
  width_ = height_ = 0;
}

VulkanEdgeStage::~VulkanEdgeStage() {
  if (!ctx_) return;
  const VulkanFunctions& vk = ctx_->vk();
  VkDevice dev = ctx_->device();
  vk.vkDeviceWaitIdle(dev);
  ReleaseFrameBuffers();
  if (query_pool_ != VK_NULL_HANDLE) vk.vkDestroyQueryPool(dev, query_pool_, nullptr);
  if (fence_ != VK_NULL_HANDLE) vk.vkDestroyFence(dev, fence_, nullptr);
  if (command_pool_ != VK_NULL_HANDLE) vk.vkDestroyCommandPool(dev, command_pool_, nullptr);
  if (descriptor_pool_ != VK_NULL_HANDLE) vk.vkDestroyDescriptorPool(dev, descriptor_pool_, nullptr);
  for (VkPipeline p : pipelines_)
    if (p != VK_NULL_HANDLE) vk.vkDestroyPipeline(dev, p, nullptr);
  if (pipeline_layout_ != VK_NULL_HANDLE) vk.vkDestroyPipelineLayout(dev, pipeline_layout_, nullptr);
  if (set_layout_ != VK_NULL_HANDLE) vk.vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
}

Status VulkanEdgeStage::Resize(int width, int height) {
  if (width == width_ && height == height_) return Status::Ok();
  ctx_->vk().vkDeviceWaitIdle(ctx_->device());
  ReleaseFrameBuffers();
  chunks_ = CeilDiv(static_cast<std::uint64_t>(width), 16);
  padded_row_vec4_ = chunks_ + 2;
  mask_words_ = CeilDiv(static_cast<std::uint64_t>(width), 32);
  const VkDeviceSize frame = 16ull * padded_row_vec4_ * (static_cast<VkDeviceSize>(height) + 2);
  // 16-bit planes (dx, dy): rows of whole mask words (32 pixels = 4 uvec4), so nms.comp reads
  // a word's four uvec4 without bounds tests. The edge map: rows of whole 16-pixel chunks.
  const VkDeviceSize packed16 = 64ull * mask_words_ * height, packed8 = 16ull * chunks_ * height;
  const VkDeviceSize sizes[kNumBindings] = {frame, frame, packed16, packed16, 4 * (kMaxMagnitude + 1), 16,
                                            8ull * mask_words_ * height, 4 * (kRoundsPerSubmit + 1), packed8};
  const VkDeviceSize largest = std::max(frame, packed16);
  if (largest > ctx_->properties().limits.maxStorageBufferRange)
    return {StatusCode::kUnavailable, "frame of " + std::to_string(width) + "x" + std::to_string(height) +
                                          " pixels exceeds the device's storage buffer range (" +
                                          std::to_string(ctx_->properties().limits.maxStorageBufferRange) + " bytes)"};
  // The frame, dx, dy and the edge map live in host-visible memory that the shaders read and write
  // directly: no staging copies (on lavapipe, and on unified-memory GPUs, it is the same memory).
  for (int b = 0; b < kNumBindings; ++b) {
    const bool host_visible = b == kImage || b == kDx || b == kDy || b == kFlags || b == kEdges;
    Status st = ctx_->CreateBuffer(sizes[b], host_visible, &buffers_[b]);
    if (!st.ok()) return st;
  }

  VkDescriptorBufferInfo infos[kNumBindings];
  VkWriteDescriptorSet writes[kNumBindings];
  for (int b = 0; b < kNumBindings; ++b) {
    infos[b] = VkDescriptorBufferInfo{buffers_[b].buffer, 0, VK_WHOLE_SIZE};
    writes[b] = VkWriteDescriptorSet{};
    writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[b].dstSet = set_;
    writes[b].dstBinding = static_cast<std::uint32_t>(b);
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  ctx_->vk().vkUpdateDescriptorSets(ctx_->device(), kNumBindings, writes, 0, nullptr);
  width_ = width;
  height_ = height;
  return Status::Ok();
}

void VulkanEdgeStage::Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t gx, std::uint32_t gy,
                               const std::uint32_t* push) {
  const VulkanFunctions& vk = ctx_->vk();
  vk.vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_[p]);
  vk.vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_, 0, 1, &set_, 0, nullptr);
  vk.vkCmdPushConstants(cb, pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushWords * sizeof(std::uint32_t), push);
  vk.vkCmdDispatch(cb, gx, gy, 1);
}

// Linear work spread over a 2-D grid: the shaders index id = gid.y * (groups.x * local_size_x) + gid.x.
void VulkanEdgeStage::Dispatch1D(VkCommandBuffer cb, Pipeline p, std::uint64_t groups, const std::uint32_t* push) {
  const std::uint32_t gx = static_cast<std::uint32_t>(std::min<std::uint64_t>(std::max<std::uint64_t>(groups, 1), kMaxGroups));
  Dispatch(cb, p, gx, CeilDiv(std::max<std::uint64_t>(groups, 1), gx), push);
}

void VulkanEdgeStage::Barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access,
                              VkPipelineStageFlags dst, VkAccessFlags dst_access) {
  VkMemoryBarrier mb{};
  mb.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  mb.srcAccessMask = src_access;
  mb.dstAccessMask = dst_access;
  ctx_->vk().vkCmdPipelineBarrier(cb, src, dst, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

// flags[0] = 1, flags[1..] = 0; kRoundsPerSubmit hysteresis rounds; edge_sign; host visibility.
void VulkanEdgeStage::RecordHysteresisAndOutput(VkCommandBuffer cb) {
  const VulkanFunctions& vk = ctx_->vk();
  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  vk.vkCmdFillBuffer(cb, buffers_[kFlags].buffer, 0, 4, 1u);
  vk.vkCmdFillBuffer(cb, buffers_[kFlags].buffer, 4, 4 * kRoundsPerSubmit, 0u);
  Barrier(cb, kTransfer | kCompute, VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  std::uint32_t push[6] = {static_cast<std::uint32_t>(width_), static_cast<std::uint32_t>(height_), 0, mask_words_,
                           chunks_, 4 * mask_words_};
  for (int round = 0; round < kRoundsPerSubmit; ++round) {
    push[2] = static_cast<std::uint32_t>(round);
    Dispatch(cb, kHysteresis, CeilDiv(mask_words_, kHysteresisGroup), 1, push);
    Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  }
  push[2] = 0;
  Dispatch1D(cb, kEdgeSign, CeilDiv(static_cast<std::uint64_t>(chunks_) * height_, kGroup), push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

Status VulkanEdgeStage::Submit(VkCommandBuffer cb) {
  const VulkanFunctions& vk = ctx_->vk();
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  VkResult r = vk.vkQueueSubmit(ctx_->queue(), 1, &si, fence_);
  if (r != VK_SUCCESS) return VkFail("vkQueueSubmit", r);
  r = vk.vkWaitForFences(ctx_->device(), 1, &fence_, VK_TRUE, UINT64_MAX);
  vk.vkResetFences(ctx_->device(), 1, &fence_);
  if (r != VK_SUCCESS) return VkFail("vkWaitForFences", r);
  return Status::Ok();
}

Status VulkanEdgeStage::Run(const ImageView& image, const Options& options, std::int16_t* dx, std::int16_t* dy,
                            std::uint8_t* edge_map) {
  if (image.data == nullptr || image.width <= 0 || image.height <= 0 || image.stride < image.width)
    return {StatusCode::kInvalidArgument, "VulkanEdgeStage::Run: invalid image view"};
  if (dx == nullptr || dy == nullptr || edge_map == nullptr)
    return {StatusCode::kInvalidArgument, "VulkanEdgeStage::Run: null output buffer"};
  Status st = Resize(image.width, image.height);
  if (!st.ok()) return st;
  const VulkanFunctions& vk = ctx_->vk();
  const int w = width_, h = height_;
  const std::uint64_t n = static_cast<std::uint64_t>(w) * h;

  // Upload into the padded frame of shaders/gaussian.comp: 16 pad bytes, the row, the rest of the
  // row's chunks and 16 more pad bytes, all pads repeating the nearest pixel; rows -1 and h repeat
  // rows 0 and h - 1. That is the replicate border, so the shaders need no border tests.
  const std::size_t row_bytes = 16 * static_cast<std::size_t>(padded_row_vec4_);
  auto* up = static_cast<std::uint8_t*>(buffers_[kImage].mapped);
  for (int r = -1; r <= h; ++r) {
    const std::uint8_t* src = image.data + std::clamp(r, 0, h - 1) * image.stride;
    std::uint8_t* dst = up + static_cast<std::size_t>(r + 1) * row_bytes;
    std::memset(dst, src[0], 16);
    std::memcpy(dst + 16, src, static_cast<std::size_t>(w));
    std::memset(dst + 16 + w, src[w - 1], row_bytes - 16 - static_cast<std::size_t>(w));
  }
  ctx_->FlushHostWrites(buffers_[kImage]);

  // 1000 * below >= high_permille * N  <=>  below >= ceil(high_permille * N / 1000).
  const std::uint64_t need = (static_cast<std::uint64_t>(std::max(options.canny_high_permille, 0)) * n + 999) / 1000;
  const std::uint32_t uw = static_cast<std::uint32_t>(w), uh = static_cast<std::uint32_t>(h);
  const std::uint64_t row_blocks = CeilDiv(static_cast<std::uint64_t>(h), kRowsPerInvocation);
  const std::uint64_t chunk_groups = CeilDiv(static_cast<std::uint64_t>(chunks_) * row_blocks, kGroup);

  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  const bool timed = query_pool_ != VK_NULL_HANDLE;
  double device_ms = 0;
  auto read_time = [&]() {
    std::uint64_t ts[2] = {0, 0};
    if (vk.vkGetQueryPoolResults(ctx_->device(), query_pool_, 0, 2, sizeof(ts), ts, sizeof(std::uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS) {
      const std::uint64_t mask = ctx_->timestamp_valid_bits() >= 64 ? ~0ull : ((1ull << ctx_->timestamp_valid_bits()) - 1);
      device_ms += static_cast<double>((ts[1] - ts[0]) & mask) * ctx_->timestamp_period_ns() * 1e-6;
    }
  };

  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VkCommandBuffer cb = frame_cb_;
  vk.vkResetCommandBuffer(cb, 0);
  vk.vkBeginCommandBuffer(cb, &begin);
  if (timed) {
    vk.vkCmdResetQueryPool(cb, query_pool_, 0, 2);
    vk.vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, query_pool_, 0);
  }
  // The host wrote the frame before the submit (visible to it); the previous frame's work is done
  // (fence), so clearing the histogram needs no barrier before it.
  vk.vkCmdFillBuffer(cb, buffers_[kHist].buffer, 0, VK_WHOLE_SIZE, 0u);
  Barrier(cb, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t plane_row_vec4 = 4 * mask_words_;
  const std::uint32_t frame_push[6] = {uw, uh, 0, padded_row_vec4_, chunks_, plane_row_vec4};
  if (options.gaussian_blur) {
    Dispatch1D(cb, kGaussian, chunk_groups, frame_push);
    Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  }
  Dispatch1D(cb, options.gaussian_blur ? kSobel : kSobelRaw, chunk_groups, frame_push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t mask_push[6] = {uw, uh, 0, mask_words_, chunks_, plane_row_vec4};
  Dispatch1D(cb, kHistogram, CeilDiv(static_cast<std::uint64_t>(plane_row_vec4) * h, kHistVec4PerGroup), mask_push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t select_push[6] = {uw, uh, static_cast<std::uint32_t>(need),
                                        static_cast<std::uint32_t>(options.canny_low_permille),
                                        static_cast<std::uint32_t>(options.canny_min_high), 0};
  Dispatch(cb, kSelect, 1, 1, select_push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  Dispatch1D(cb, kNms, CeilDiv(static_cast<std::uint64_t>(mask_words_) * row_blocks, kGroup), mask_push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  RecordHysteresisAndOutput(cb);
  if (timed) vk.vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, 1);
  VkResult r = vk.vkEndCommandBuffer(cb);
  if (r != VK_SUCCESS) return VkFail("vkEndCommandBuffer", r);
  st = Submit(cb);
  if (!st.ok()) return st;
  if (timed) read_time();
  // More hysteresis rounds while the last one changed something (bounded by the contract).
  const auto* flags = static_cast<const volatile std::uint32_t*>(buffers_[kFlags].mapped);
  int rounds = kRoundsPerSubmit;
  const std::uint64_t max_rounds = n + 1 + kRoundsPerSubmit;
  for (;;) {
    ctx_->InvalidateForHostReads(buffers_[kFlags]);
    if (flags[kRoundsPerSubmit] == 0) break;
    if (static_cast<std::uint64_t>(rounds) >= max_rounds)
      return {StatusCode::kInternal, "Vulkan hysteresis did not converge within width * height rounds"};
    cb = more_rounds_cb_;
    vk.vkResetCommandBuffer(cb, 0);
    vk.vkBeginCommandBuffer(cb, &begin);
    if (timed) {
      vk.vkCmdResetQueryPool(cb, query_pool_, 0, 2);
      vk.vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, query_pool_, 0);
    }
    RecordHysteresisAndOutput(cb);
    if (timed) vk.vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, 1);
    r = vk.vkEndCommandBuffer(cb);
    if (r != VK_SUCCESS) return VkFail("vkEndCommandBuffer", r);
    st = Submit(cb);
    if (!st.ok()) return st;
    if (timed) read_time();
    rounds += kRoundsPerSubmit;
  }
  last_rounds_ = rounds;
  last_device_ms_ = timed ? device_ms : -1;

  // Device rows: dx / dy 32 * mask_words_ elements apart, the edge map 16 * chunks_ bytes; the
  // caller's rows are `w` apart.
  for (int b : {kDx, kDy, kEdges}) ctx_->InvalidateForHostReads(buffers_[b]);
  const std::size_t stride = 16 * static_cast<std::size_t>(chunks_);
  const std::size_t plane_stride = 32 * static_cast<std::size_t>(mask_words_);
  const auto* gx = static_cast<const std::int16_t*>(buffers_[kDx].mapped);
  const auto* gy = static_cast<const std::int16_t*>(buffers_[kDy].mapped);
  const auto* edges = static_cast<const std::uint8_t*>(buffers_[kEdges].mapped);
  const std::size_t uwz = static_cast<std::size_t>(w);
  for (int y = 0; y < h; ++y) {
    std::memcpy(dx + y * uwz, gx + y * plane_stride, uwz * sizeof(std::int16_t));
    std::memcpy(dy + y * uwz, gy + y * plane_stride, uwz * sizeof(std::int16_t));
    std::memcpy(edge_map + y * uwz, edges + y * stride, uwz);
  }
  return Status::Ok();
}

}  // namespace ellipsekit
