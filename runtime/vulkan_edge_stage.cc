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

enum Binding : int { kImage, kBlurred, kDx, kDy, kMag, kHist, kThresholds, kMap, kFlags, kEdges };

constexpr std::uint32_t kGroup1D = 256;          // local_size_x of the 1-D shaders
constexpr std::uint32_t kTile = 16;              // local size of the 2-D shaders
constexpr std::uint32_t kHistPixelsPerGroup = 256 * 16;
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

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push_)};
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
    std::uint32_t mode;  // constant_id 0 (canny_thresholds.comp only)
  };
  const Source sources[kNumPipelines] = {
      {kGaussianSpv, sizeof(kGaussianSpv), 0},         {kSobelSpv, sizeof(kSobelSpv), 0},
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
    cpci.stage.pSpecializationInfo = (sources[p].code == kCannyThresholdsSpv) ? &spec : nullptr;
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
  ctx_->DestroyBuffer(&upload_);
  ctx_->DestroyBuffer(&download_);
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
  const VkDeviceSize n = static_cast<VkDeviceSize>(width) * height;
  const VkDeviceSize packed8 = 4 * ((n + 3) / 4), packed16 = 4 * ((n + 1) / 2), words = 4 * n;
  const VkDeviceSize sizes[kNumBindings] = {packed8, words, packed16, packed16, words,
                                            4 * (kMaxMagnitude + 1), 16, words,
                                            4 * (kRoundsPerSubmit + 1), packed8};
  if (words > ctx_->properties().limits.maxStorageBufferRange)
    return {StatusCode::kUnavailable, "frame of " + std::to_string(n) + " pixels exceeds the device's storage buffer range (" +
                                          std::to_string(ctx_->properties().limits.maxStorageBufferRange) + " bytes)"};
  for (int b = 0; b < kNumBindings; ++b) {
    Status st = ctx_->CreateBuffer(sizes[b], b == kFlags, &buffers_[b]);
    if (!st.ok()) return st;
  }
  Status st = ctx_->CreateBuffer(packed8, true, &upload_);
  if (!st.ok()) return st;
  dx_bytes_ = packed16;
  edge_bytes_ = packed8;
  st = ctx_->CreateBuffer(2 * dx_bytes_ + edge_bytes_, true, &download_);
  if (!st.ok()) return st;

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
  vk.vkCmdPushConstants(cb, pipeline_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push_), push);
  vk.vkCmdDispatch(cb, gx, gy, 1);
}

// Linear work spread over a 2-D grid: the shaders index word = gid.y * (groups.x * 256) + gid.x.
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

// flags[0] = 1, flags[1..] = 0; kRoundsPerSubmit hysteresis rounds; edge_sign; downloads.
void VulkanEdgeStage::RecordHysteresisAndOutput(VkCommandBuffer cb, bool download_gradients) {
  const VulkanFunctions& vk = ctx_->vk();
  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  vk.vkCmdFillBuffer(cb, buffers_[kFlags].buffer, 0, 4, 1u);
  vk.vkCmdFillBuffer(cb, buffers_[kFlags].buffer, 4, 4 * kRoundsPerSubmit, 0u);
  Barrier(cb, kTransfer | kCompute, VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  std::uint32_t push[6] = {push_[0], push_[1], 0, 0, 0, 0};
  for (int round = 0; round < kRoundsPerSubmit; ++round) {
    push[2] = static_cast<std::uint32_t>(round);
    Dispatch(cb, kHysteresis, CeilDiv(width_, kTile), CeilDiv(height_, kTile), push);
    Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  }
  const std::uint64_t n = static_cast<std::uint64_t>(width_) * height_;
  Dispatch1D(cb, kEdgeSign, CeilDiv(CeilDiv(n, 4), kGroup1D), push_);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kTransfer, VK_ACCESS_TRANSFER_READ_BIT);
  VkBufferCopy copies[3] = {{0, 2 * dx_bytes_, edge_bytes_}, {0, 0, dx_bytes_}, {0, dx_bytes_, dx_bytes_}};
  vk.vkCmdCopyBuffer(cb, buffers_[kEdges].buffer, download_.buffer, 1, &copies[0]);
  if (download_gradients) {
    vk.vkCmdCopyBuffer(cb, buffers_[kDx].buffer, download_.buffer, 1, &copies[1]);
    vk.vkCmdCopyBuffer(cb, buffers_[kDy].buffer, download_.buffer, 1, &copies[2]);
  }
  Barrier(cb, kTransfer | kCompute, VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT,
          VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
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

  // Upload: rows packed to stride = width (the shaders read 4 pixels per word).
  auto* up = static_cast<std::uint8_t*>(upload_.mapped);
  for (int y = 0; y < h; ++y) std::memcpy(up + static_cast<std::size_t>(y) * w, image.data + y * image.stride, w);
  std::memset(up + n, 0, upload_.size - n);
  ctx_->FlushHostWrites(upload_);

  // 1000 * below >= high_permille * N  <=>  below >= ceil(high_permille * N / 1000).
  const std::uint64_t need = (static_cast<std::uint64_t>(std::max(options.canny_high_permille, 0)) * n + 999) / 1000;
  push_[0] = static_cast<std::uint32_t>(w);
  push_[1] = static_cast<std::uint32_t>(h);
  push_[2] = push_[3] = push_[4] = push_[5] = 0;

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
  // Upload and clear the histogram; the previous frame's reads are done (fence), so no WAR barrier.
  VkBufferCopy up_copy{0, 0, upload_.size};
  vk.vkCmdCopyBuffer(cb, upload_.buffer, buffers_[kImage].buffer, 1, &up_copy);
  vk.vkCmdFillBuffer(cb, buffers_[kHist].buffer, 0, VK_WHOLE_SIZE, 0u);
  Barrier(cb, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kRW);
  if (options.gaussian_blur) {
    Dispatch(cb, kGaussian, CeilDiv(w, kTile), CeilDiv(h, kTile), push_);
    Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  }
  std::uint32_t push[6] = {push_[0], push_[1], options.gaussian_blur ? 1u : 0u, 0, 0, 0};
  Dispatch1D(cb, kSobel, CeilDiv(CeilDiv(n, 2), kGroup1D), push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  Dispatch1D(cb, kHistogram, CeilDiv(n, kHistPixelsPerGroup), push_);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t select_push[6] = {push_[0], push_[1], static_cast<std::uint32_t>(need),
                                        static_cast<std::uint32_t>(options.canny_low_permille),
                                        static_cast<std::uint32_t>(options.canny_min_high), 0};
  Dispatch(cb, kSelect, 1, 1, select_push);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  Dispatch(cb, kNms, CeilDiv(w, kTile), CeilDiv(h, kTile), push_);
  Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  RecordHysteresisAndOutput(cb, /*download_gradients=*/true);
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
    RecordHysteresisAndOutput(cb, /*download_gradients=*/false);
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

  ctx_->InvalidateForHostReads(download_);
  const auto* down = static_cast<const std::uint8_t*>(download_.mapped);
  std::memcpy(dx, down, n * sizeof(std::int16_t));
  std::memcpy(dy, down + dx_bytes_, n * sizeof(std::int16_t));
  std::memcpy(edge_map, down + 2 * dx_bytes_, n);
  return Status::Ok();
}

}  // namespace ellipsekit
