#include "runtime/vulkan_edge_stage.h"

#include <stdint.h>  // the generated SPIR-V headers use ::uint32_t

#include <algorithm>
#include <cstring>
#include <string>

#include "kernels/canny_thresholds.h"
#include "shaders/gaussian_sobel_thresholds.spv.h"
#include "shaders/hysteresis.spv.h"
#include "shaders/hysteresis_blocks.spv.h"
#include "shaders/hysteresis_rmw.spv.h"
#include "shaders/nms_edge_sign.spv.h"

namespace ellipsekit {

namespace {

enum Binding : int { kImage, kDx, kDy, kHist, kThresholds, kMasks, kEdges };

constexpr std::uint32_t kGroup = 64;             // local_size_x of gaussian_sobel_thresholds, nms
constexpr std::uint32_t kRowsPerInvocation = 8;  // kRows of gaussian_sobel_thresholds.comp, nms.comp
constexpr std::uint32_t kMaxGroups = 65535;      // guaranteed maxComputeWorkGroupCount per axis
constexpr std::uint32_t kHysteresisBlockRows = 64;  // kBlockRows of hysteresis_sweep.glsl

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
  // constant_id 0: gaussian_sobel_thresholds.comp BLUR.
  const VulkanProgram::Shader shaders[kNumPipelines] = {
      {kGaussianSobelThresholdsSpv, sizeof(kGaussianSobelThresholdsSpv), true, 1},
      {kGaussianSobelThresholdsSpv, sizeof(kGaussianSobelThresholdsSpv), true, 0},
      {kNmsEdgeSignSpv, sizeof(kNmsEdgeSignSpv)},
      // Relaxed atomics under the Vulkan memory model where the device has it, else atomicOr and
      // no blocks' pass (its slot holds the finishing shader again, never dispatched).
      ctx_->memory_model() ? VulkanProgram::Shader{kHysteresisBlocksSpv, sizeof(kHysteresisBlocksSpv)}
                           : VulkanProgram::Shader{kHysteresisRmwSpv, sizeof(kHysteresisRmwSpv)},
      ctx_->memory_model() ? VulkanProgram::Shader{kHysteresisSpv, sizeof(kHysteresisSpv)}
                           : VulkanProgram::Shader{kHysteresisRmwSpv, sizeof(kHysteresisRmwSpv)}};
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
  recorded_ = Recording{};  // the commands name the old buffers
  chunks_ = CeilDiv(static_cast<std::uint64_t>(width), 16);
  padded_row_vec4_ = chunks_ + 2;
  mask_words_ = CeilDiv(static_cast<std::uint64_t>(width), 32);
  const VkDeviceSize frame = 16ull * padded_row_vec4_ * (static_cast<VkDeviceSize>(height) + 2);
  // 16-bit planes (dx, dy): rows of whole mask words (32 pixels = 4 uvec4), so nms.comp reads
  // a word's four uvec4 without bounds tests. The edge map: rows of whole mask words too.
  const VkDeviceSize packed16 = 64ull * mask_words_ * height, packed8 = 32ull * mask_words_ * height;
  const VkDeviceSize most_tiles = static_cast<VkDeviceSize>(TilesAlong(width, kNmsMinTileShift)) *
                                 TilesAlong(height, kNmsMinTileShift);
  const VkDeviceSize sizes[kNumBindings] = {frame, packed16, packed16, 4 * (kMaxMagnitude + 2 + most_tiles),
                                            8 * most_tiles, 8ull * mask_words_ * height, packed8};
  const VkDeviceSize largest = std::max(frame, packed16);
  if (largest > ctx_->properties().limits.maxStorageBufferRange)
    return {StatusCode::kUnavailable, "frame of " + std::to_string(width) + "x" + std::to_string(height) +
                                          " pixels exceeds the device's storage buffer range (" +
                                          std::to_string(ctx_->properties().limits.maxStorageBufferRange) + " bytes)"};
  // The frame, dx, dy and the edge map live in host-visible memory that the shaders read and write
  // directly: no staging copies (on lavapipe, and on unified-memory GPUs, it is the same memory).
  for (int b = 0; b < kNumBindings; ++b) {
    const bool host_visible = b == kImage || b == kDx || b == kDy || b == kEdges;
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

// Measured on an H200 (edge_stage/vulkan_steps, docs/vulkan.md): the edge stage at 640x480 took
// 1.65 ms without a blocks' pass, 0.91 / 0.96 / 1.03 with 1 / 2 / 4; at 1920x1080 6.77 ms without,
// 4.74 / 4.53 / 3.59 / 3.71 with 1 / 2 / 4 / 8: about one pass per 256 rows. On a CPU device
// (lavapipe) the one workgroup is one thread among others and a pass gained nothing measurable
// (640x480: 3.26 ms of device time without, 3.31 / 3.61 with 1 / 2), so none runs there.
int VulkanEdgeStage::HysteresisBlockPasses(int height) const {
  if (!ctx_->memory_model()) return 0;  // hysteresis_blocks.comp needs it
  if (block_passes_ >= 0) return block_passes_;
  if (ctx_->properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) return 0;
  return static_cast<int>(CeilDiv(static_cast<std::uint64_t>(height), 256));
}

static_assert(VulkanEdgeStage::kNumSteps + 1 <= VulkanProgram::kMaxTimestamps, "one query per step end, plus the start");

const char* VulkanEdgeStage::StepName(Step s) {
  switch (s) {
    case kStepGaussianSobelThresholds: return "gaussian_sobel_thresholds";
    case kStepNmsEdgeSign: return "nms_edge_sign";
    case kStepHysteresisBlocks: return "hysteresis_blocks";
    case kStepHysteresis: return "hysteresis";
    case kNumSteps: break;
  }
  return "?";
}

// The frame's commands, recorded once for a frame size and set of options and then re-submitted
// as they are: the buffers, the push constants and the dispatch sizes depend on nothing else.
Status VulkanEdgeStage::Record(const Recording& rec) {
  recorded_ = Recording{};
  const VulkanFunctions& vk = ctx_->vk();
  const std::uint32_t uw = static_cast<std::uint32_t>(rec.width), uh = static_cast<std::uint32_t>(rec.height);
  const std::uint64_t row_blocks = CeilDiv(static_cast<std::uint64_t>(rec.height), kRowsPerInvocation);
  const std::uint64_t chunk_groups = CeilDiv(static_cast<std::uint64_t>(chunks_) * row_blocks, kGroup);
  const int shift = static_cast<int>(rec.tile_shift);
  const std::uint32_t tiles_x = static_cast<std::uint32_t>(TilesAlong(rec.width, shift));
  const std::uint32_t tiles = tiles_x * static_cast<std::uint32_t>(TilesAlong(rec.height, shift));
  constexpr VkPipelineStageFlags kCompute = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  constexpr VkPipelineStageFlags kTransfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  constexpr VkAccessFlags kRW = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  // Query 0 before the first step, query s + 1 after step s (VulkanEdgeStage::Step).
  auto timestamp = [&](VkCommandBuffer cb, Step s) {
    if (rec.timed) program_.Timestamp(cb, s + 1);
  };

  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  VkCommandBuffer cb = program_.command_buffer(0);
  vk.vkResetCommandBuffer(cb, 0);
  vk.vkBeginCommandBuffer(cb, &begin);
  if (rec.timed) program_.StartTimestamps(cb, 0, kNumSteps + 1);
  // The host wrote the frame before the submit (visible to it); the previous frame's work is done
  // (fence), so clearing the histogram needs no barrier before it.
  vk.vkCmdFillBuffer(cb, buffers_[kHist].buffer, 0, VK_WHOLE_SIZE, 0u);
  program_.Barrier(cb, kTransfer, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute, kRW);
  const std::uint32_t plane_row_vec4 = 4 * mask_words_;
  const std::uint32_t frame_push[kPushWords] = {uw,      uh,           rec.need,         padded_row_vec4_,
                                                chunks_, plane_row_vec4, rec.low_permille, rec.min_high,
                                                rec.contrast_need, rec.contrast_ref, rec.noise_need,
                                                rec.tile_shift, tiles_x, tiles};
  Dispatch1D(cb, rec.blur ? kGaussianSobelThresholds : kSobelThresholds, chunk_groups, frame_push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  timestamp(cb, kStepGaussianSobelThresholds);
  const std::uint32_t mask_push[kPushWords] = {uw, uh, 0, mask_words_, chunks_, plane_row_vec4, rec.tile_shift,
                                               tiles_x, 0, 0, 0, 0, 0, 0};
  Dispatch1D(cb, kNmsEdgeSign, CeilDiv(static_cast<std::uint64_t>(mask_words_) * row_blocks, kGroup), mask_push);
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
  timestamp(cb, kStepNmsEdgeSign);
  {
    const std::uint64_t blocks = static_cast<std::uint64_t>(mask_words_) * CeilDiv(uh, kHysteresisBlockRows);
    for (int k = 0; k < rec.block_passes; ++k) {
      Dispatch1D(cb, kHysteresisBlocks, CeilDiv(blocks, kGroup), mask_push);
      program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, kCompute, kRW);
    }
  }
  timestamp(cb, kStepHysteresisBlocks);
  Dispatch(cb, kHysteresis, 1, 1, mask_push);  // one workgroup (shaders/hysteresis_sweep.glsl)
  program_.Barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  timestamp(cb, kStepHysteresis);
  const VkResult r = vk.vkEndCommandBuffer(cb);
  if (r != VK_SUCCESS) return VkFail("vkEndCommandBuffer", r);
  recorded_ = rec;
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
  const int w = width_, h = height_;
  const std::uint64_t counted = static_cast<std::uint64_t>(w) * HistogramRows(h);  // histogram's N

  // Upload into the padded frame of shaders/gaussian_sobel_thresholds.comp: 16 pad bytes, the row, the rest of the
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

  // 1000 * below >= p * N  <=>  below >= ceil(p * N / 1000).
  auto need_for = [counted](int permille) {
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(std::max(permille, 0)) * counted + 999) / 1000);
  };
  const Recording want{w,
                       h,
                       options.gaussian_blur,
                       timing_ && program_.timed(),
                       HysteresisBlockPasses(h),
                       need_for(options.canny_high_permille),
                       static_cast<std::uint32_t>(options.canny_low_permille),
                       static_cast<std::uint32_t>(options.canny_min_high),
                       need_for(kContrastPermille),
                       static_cast<std::uint32_t>(options.canny_contrast_ref),
                       need_for(kNoisePermille),
                       static_cast<std::uint32_t>(CannyTileShift(options.canny_tile))};
  if (!(recorded_ == want)) {
    st = Record(want);
    if (!st.ok()) return st;
  }
  st = program_.SubmitAndWait(program_.command_buffer(0));
  if (!st.ok()) return st;
  last_device_ms_ = -1;
  for (double& ms : last_step_ms_) ms = -1;
  if (want.timed) {
    double step_ms[kNumSteps] = {};
    program_.AddIntervalsMs(0, kNumSteps, step_ms);
    last_device_ms_ = 0;
    for (int s = 0; s < kNumSteps; ++s) {
      last_step_ms_[s] = step_ms[s];
      last_device_ms_ += step_ms[s];
    }
  }

  // Device rows: dx / dy and the edge map 32 * mask_words_ elements apart; the caller's rows are
  // `w` apart.
  for (int b : {kDx, kDy, kEdges}) ctx_->InvalidateForHostReads(buffers_[b]);
  const std::size_t plane_stride = 32 * static_cast<std::size_t>(mask_words_);
  const auto* gx = static_cast<const std::int16_t*>(buffers_[kDx].mapped);
  const auto* gy = static_cast<const std::int16_t*>(buffers_[kDy].mapped);
  const auto* edges = static_cast<const std::uint8_t*>(buffers_[kEdges].mapped);
  const std::size_t uwz = static_cast<std::size_t>(w);
  for (int y = 0; y < h; ++y) {
    std::memcpy(dx + y * uwz, gx + y * plane_stride, uwz * sizeof(std::int16_t));
    std::memcpy(dy + y * uwz, gy + y * plane_stride, uwz * sizeof(std::int16_t));
    std::memcpy(edge_map + y * uwz, edges + y * plane_stride, uwz);
  }
  return Status::Ok();
}

}  // namespace ellipsekit
