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
#include "shaders/hysteresis_rmw.spv.h"
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

Status VkFail(const char* what, VkResult r) { return VulkanFailure(what, r); }

std::uint32_t CeilDiv(std::uint64_t a, std::uint64_t b) { return static_cast<std::uint32_t>((a + b - 1) / b); }

}  // namespace

Status VulkanEdgeStage::Create(std::unique_ptr<VulkanEdgeStage>* out) {
  std::unique_ptr<VulkanEdgeStage> stage(new VulkanEdgeStage());
  std::unique_ptr<VulkanContext> ctx;
  Status st = VulkanContext::Create(&ctx);
  if (!st.ok()) return st;
  stage->ctx_ = std::move(ctx);
  st = stage->Init();
  if (!st.ok()) return st;
  *out = std::move(stage);
  return Status::Ok();
}

Status VulkanEdgeStage::Init() {
  // constant_id 0: canny_thresholds.comp MODE, sobel.comp FROM_BLURRED (ignored by the others).
  const VulkanProgram::Shader shaders[kNumPipelines] = {
      {kGaussianSpv, sizeof(kGaussianSpv), true, 0},         {kSobelSpv, sizeof(kSobelSpv), true, 1},
      {kSobelSpv, sizeof(kSobelSpv), true, 0},
      {kCannyThresholdsSpv, sizeof(kCannyThresholdsSpv), true, 0},
      {kCannyThresholdsSpv, sizeof(kCannyThresholdsSpv), true, 1},
      {kNmsSpv, sizeof(kNmsSpv), true, 0},
      // Relaxed atomics under the Vulkan memory model where the device has it, else atomicOr.
      ctx_->memory_model() ? VulkanProgram::Shader{kHysteresisSpv, sizeof(kHysteresisSpv), true, 0}
                           : VulkanProgram::Shader{kHysteresisRmwSpv, sizeof(kHysteresisRmwSpv), true, 0},
      {kEdgeSignSpv, sizeof(kEdgeSignSpv), true, 0}};
  return program_.Create(ctx_.get(), kNumBindings, kPushWords * sizeof(std::uint32_t), shaders, kNumPipelines);
}

void VulkanEdgeStage::ReleaseFrameBuffers() {
  for (VulkanBuffer& b : buffers_) ctx_->DestroyBuffer(&b);
  width_ = height_ = 0;
}

VulkanEdgeStage::~VulkanEdgeStage() {
  if (!ctx_) return;
  ctx_->vk().vkDeviceWaitIdle(ctx_->device());
  ReleaseFrameBuffers();
  // program_ releases its objects next, then ctx_ (if no other stage shares it).
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

  program_.BindBuffers(buffers_);
  width_ = width;
  height_ = height;
  return Status::Ok();
}

void VulkanEdgeStage::Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t gx, std::uint32_t gy,
                               const std::uint32_t* push) {
  program_.Dispatch(cb, p, kPushWords * sizeof(std::uint32_t), push, gx, gy);
}

// Linear work spread over a 2-D grid: the shaders index id = gid.y * (groups.x * local_size_x) + gid.x.
void VulkanEdgeStage::Dispatch1D(VkCommandBuffer cb, Pipeline p, std::uint64_t groups, const std::uint32_t* push) {
  const std::uint32_t gx = static_cast<std::uint32_t>(std::min<std::uint64_t>(std::max<std::uint64_t>(groups, 1), kMaxGroups));
  Dispatch(cb, p, gx, CeilDiv(std::max<std::uint64_t>(groups, 1), gx), push);
}

// flags[0] = 1, flags[1..] = 0; kRoundsPerSubmit hysteresis rounds; edge_sign; host visibility.
static_assert(VulkanEdgeStage::kNumSteps + 1 <= VulkanProgram::kMaxTimestamps, "one query per step end, plus the start");

const char* VulkanEdgeStage::StepName(Step s) {
  switch (s) {
    case kStepGaussian: return "gaussian";
    case kStepSobel: return "sobel";
    case kStepThresholds: return "thresholds";
    case kStepNms: return "nms";
    case kStepHysteresis: return "hysteresis";
    case kStepEdgeSign: return "edge_sign";
    case kNumSteps: break;
  }
  return "?";
}

void VulkanEdgeStage::RecordHysteresisAndOutput(VkCommandBuffer cb) {
  const VulkanFunctions& vk = ctx_->vk();
  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  vk.vkCmdFillBuffer(cb, buffers_[kFlags].buffer, 0, 4, 1u);
  vk.vkCmdFillBuffer(cb, buffers_[kFlags].buffer, 4, 4 * kRoundsPerSubmit, 0u);
  program_.Barrier(cb, kTransfer | kCompute, VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  std::uint32_t push[6] = {static_cast<std::uint32_t>(width_), static_cast<std::uint32_t>(height_), 0, mask_words_,
                           chunks_, 4 * mask_words_};
  for (int round = 0; round < kRoundsPerSubmit; ++round) {
    push[2] = static_cast<std::uint32_t>(round);
    Dispatch(cb, kHysteresis, CeilDiv(mask_words_, kHysteresisGroup), 1, push);
    program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  }
  program_.Timestamp(cb, kStepHysteresis + 1);
  push[2] = 0;
  Dispatch1D(cb, kEdgeSign, CeilDiv(static_cast<std::uint64_t>(chunks_) * height_, kGroup), push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  program_.Timestamp(cb, kStepEdgeSign + 1);
}

Status VulkanEdgeStage::Submit(VkCommandBuffer cb) { return program_.SubmitAndWait(cb); }

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
  const std::uint64_t counted = static_cast<std::uint64_t>(w) * HistogramRows(h);  // histogram's N

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
  const std::uint64_t need = (static_cast<std::uint64_t>(std::max(options.canny_high_permille, 0)) * counted + 999) / 1000;
  const std::uint32_t uw = static_cast<std::uint32_t>(w), uh = static_cast<std::uint32_t>(h);
  const std::uint64_t row_blocks = CeilDiv(static_cast<std::uint64_t>(h), kRowsPerInvocation);
  const std::uint64_t chunk_groups = CeilDiv(static_cast<std::uint64_t>(chunks_) * row_blocks, kGroup);

  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  // Query 0 before the first step, query s + 1 after step s (VulkanEdgeStage::Step).
  double step_ms[kNumSteps] = {};

  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VkCommandBuffer cb = program_.command_buffer(0);
  vk.vkResetCommandBuffer(cb, 0);
  vk.vkBeginCommandBuffer(cb, &begin);
  program_.StartTimestamps(cb, 0, kNumSteps + 1);
  // The host wrote the frame before the submit (visible to it); the previous frame's work is done
  // (fence), so clearing the histogram needs no barrier before it.
  vk.vkCmdFillBuffer(cb, buffers_[kHist].buffer, 0, VK_WHOLE_SIZE, 0u);
  program_.Barrier(cb, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t plane_row_vec4 = 4 * mask_words_;
  const std::uint32_t frame_push[6] = {uw, uh, 0, padded_row_vec4_, chunks_, plane_row_vec4};
  if (options.gaussian_blur) {
    Dispatch1D(cb, kGaussian, chunk_groups, frame_push);
    program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  }
  program_.Timestamp(cb, kStepGaussian + 1);
  Dispatch1D(cb, options.gaussian_blur ? kSobel : kSobelRaw, chunk_groups, frame_push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  program_.Timestamp(cb, kStepSobel + 1);
  const std::uint32_t mask_push[6] = {uw, uh, 0, mask_words_, chunks_, plane_row_vec4};
  Dispatch1D(cb, kHistogram, CeilDiv(static_cast<std::uint64_t>(plane_row_vec4) * HistogramRows(h), kHistVec4PerGroup),
             mask_push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t select_push[6] = {uw, uh, static_cast<std::uint32_t>(need),
                                        static_cast<std::uint32_t>(options.canny_low_permille),
                                        static_cast<std::uint32_t>(options.canny_min_high), 0};
  Dispatch(cb, kSelect, 1, 1, select_push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  program_.Timestamp(cb, kStepThresholds + 1);
  Dispatch1D(cb, kNms, CeilDiv(static_cast<std::uint64_t>(mask_words_) * row_blocks, kGroup), mask_push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  program_.Timestamp(cb, kStepNms + 1);
  RecordHysteresisAndOutput(cb);
  VkResult r = vk.vkEndCommandBuffer(cb);
  if (r != VK_SUCCESS) return VkFail("vkEndCommandBuffer", r);
  st = Submit(cb);
  if (!st.ok()) return st;
  program_.AddIntervalsMs(0, kNumSteps, step_ms);
  // More hysteresis rounds while the last one changed something (bounded by the contract).
  const auto* flags = static_cast<const volatile std::uint32_t*>(buffers_[kFlags].mapped);
  int rounds = kRoundsPerSubmit;
  const std::uint64_t max_rounds = n + 1 + kRoundsPerSubmit;
  for (;;) {
    ctx_->InvalidateForHostReads(buffers_[kFlags]);
    if (flags[kRoundsPerSubmit] == 0) break;
    if (static_cast<std::uint64_t>(rounds) >= max_rounds)
      return {StatusCode::kInternal, "Vulkan hysteresis did not converge within width * height rounds"};
    cb = program_.command_buffer(1);
    vk.vkResetCommandBuffer(cb, 0);
    vk.vkBeginCommandBuffer(cb, &begin);
    // Queries kStepHysteresis .. kStepEdgeSign + 1: start, hysteresis, edge_sign.
    program_.StartTimestamps(cb, kStepHysteresis, 3);
    RecordHysteresisAndOutput(cb);
    r = vk.vkEndCommandBuffer(cb);
    if (r != VK_SUCCESS) return VkFail("vkEndCommandBuffer", r);
    st = Submit(cb);
    if (!st.ok()) return st;
    program_.AddIntervalsMs(kStepHysteresis, 2, step_ms + kStepHysteresis);
    rounds += kRoundsPerSubmit;
  }
  last_rounds_ = rounds;
  const bool timed = program_.timed();
  last_device_ms_ = timed ? 0 : -1;
  for (int s = 0; s < kNumSteps; ++s) {
    last_step_ms_[s] = timed ? step_ms[s] : -1;
    if (timed) last_device_ms_ += step_ms[s];
  }

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
