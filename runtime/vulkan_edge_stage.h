// The edge stage on a Vulkan compute device: gaussian? -> sobel -> histogram -> thresholds -> nms
// -> hysteresis -> edge_sign, bit-identical to the scalar kernels (every step is integer; see
// shaders/*.comp for each kernel's contract and data layout).
//
// Per frame: the host writes the frame, with replicated borders, straight into a host-visible
// storage buffer; one command buffer runs all stages (a barrier after each) and kRoundsPerSubmit
// hysteresis dispatches, then edge_sign; the shaders write dx, dy and the edge map straight into
// host-visible buffers, and the host copies their rows out. One submit and one fence wait per
// frame; no staging copies. Thresholds are chosen on the device (the 64-bit product of the scalar
// rule is folded into a host-side push constant).
// Hysteresis runs on 32-pixel bit masks: each dispatch sweeps every strip to its own fixed point
// and flags whether it changed anything; only when the last dispatch of the batch still changed
// something does the host submit another batch (a dispatch that changes nothing proves the global
// fixed point). Every non-final dispatch promotes a pixel, so width * height + 1 dispatches bound it.
//
// Written for lavapipe (Mesa's CPU driver) as much as for GPUs: lavapipe runs a workgroup on one
// CPU thread, 8 invocations per SIMD instruction, and every buffer access is a loop over those
// lanes (both sides of a branch run, masked). So invocations own 16- or 32-pixel chunks of several
// rows, carry rows in registers, move whole uvec4s, and avoid data-dependent loads.
//
// Buffers and the descriptor set are made for one frame size and reused; a new size re-creates
// them. Pipelines are created once, through the context's pipeline cache. Storage is 32-bit words
// only (bytes and int16 packed in the shaders), so only core Vulkan 1.1 is needed.
// Not thread-safe: one thread at a time per instance (like a Detector).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "runtime/vulkan_context.h"
#include "runtime/vulkan_program.h"

namespace ellipsekit {

class VulkanEdgeStage {
 public:
  // Hysteresis dispatches per submit: typically one does the work and the next proves nothing
  // changes; a third spares a resubmit (fence wait) when propagation crosses strips late.
  static constexpr int kRoundsPerSubmit = 3;

  // kUnavailable with the reason when there is no Vulkan loader or usable device.
  static Status Create(std::unique_ptr<VulkanEdgeStage>* out);
  ~VulkanEdgeStage();
  VulkanEdgeStage(const VulkanEdgeStage&) = delete;
  VulkanEdgeStage& operator=(const VulkanEdgeStage&) = delete;

  // dx, dy: width * height int16 each; edge_map: width * height bytes (0 none, 1 "+", 2 "-");
  // all row-major with stride = width. Same values as the scalar edge stage of runtime/detector.cc.
  Status Run(const ImageView& image, const Options& options, std::int16_t* dx, std::int16_t* dy,
             std::uint8_t* edge_map);

  // The steps the device time is split into (timestamps after each step's barrier); thresholds is
  // the histogram and the threshold selection, hysteresis every round of every submit.
  enum Step { kStepGaussian, kStepSobel, kStepThresholds, kStepNms, kStepHysteresis, kStepEdgeSign, kNumSteps };
  static const char* StepName(Step s);

  // Device time of the last Run (GPU timestamps, all submits summed; the host's row copies into
  // and out of the host-visible buffers are not in it); -1 when the queue has no timestamps.
  double last_device_ms() const { return last_device_ms_; }
  // The same split by step (sums to last_device_ms() but for the fill commands); -1 without
  // timestamps.
  double last_step_device_ms(Step s) const { return last_step_ms_[s]; }
  // Hysteresis dispatches the last Run recorded (multiples of kRoundsPerSubmit).
  int last_hysteresis_rounds() const { return last_rounds_; }
  const std::string& device_name() const { return ctx_->device_name(); }
  // The stage's Vulkan context, for another stage to share (VulkanArcStage::Create).
  const std::shared_ptr<VulkanContext>& context() const { return ctx_; }

 private:
  // kSobel reads the Gaussian output, kSobelRaw the frame (sobel.comp, FROM_BLURRED = 1 / 0).
  enum Pipeline { kGaussian, kSobel, kSobelRaw, kHistogram, kSelect, kNms, kHysteresis, kEdgeSign, kNumPipelines };
  static constexpr int kNumBindings = 9;

  VulkanEdgeStage() = default;
  Status Init();
  Status Resize(int width, int height);
  void ReleaseFrameBuffers();
  void Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t gx, std::uint32_t gy, const std::uint32_t* push);
  void Dispatch1D(VkCommandBuffer cb, Pipeline p, std::uint64_t groups, const std::uint32_t* push);
  // Timestamps go to queries kStepHysteresis + 1 and kStepEdgeSign + 1.
  void RecordHysteresisAndOutput(VkCommandBuffer cb);
  Status Submit(VkCommandBuffer cb);

  std::shared_ptr<VulkanContext> ctx_;
  // Layouts, pipelines (indexed by Pipeline), the set, command buffers 0 (frame) and 1 (more
  // hysteresis rounds), fence, timestamps. Declared after ctx_, so it is released before it.
  VulkanProgram program_;

  // Bindings 0..8: image (packed u8), blurred, dx (packed i16), dy, hist, thresholds, masks,
  // flags, edges (packed u8). Host-visible, used in place (no staging): image, dx, dy, flags, edges.
  VulkanBuffer buffers_[kNumBindings];
  int width_ = 0, height_ = 0;
  std::uint32_t chunks_ = 0;           // 16-pixel chunks per row: ceil(width / 16)
  std::uint32_t padded_row_vec4_ = 0;  // uvec4 per row of the padded frame: chunks_ + 2
  std::uint32_t mask_words_ = 0;       // 32-pixel hysteresis mask words per row: ceil(width / 32)
  static constexpr std::uint32_t kPushWords = 6;
  double last_device_ms_ = -1;
  double last_step_ms_[kNumSteps] = {-1, -1, -1, -1, -1, -1};
  int last_rounds_ = 0;
};

}  // namespace ellipsekit
