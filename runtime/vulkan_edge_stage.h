// The edge stage on a Vulkan compute device, three dispatches per frame:
//   gaussian_sobel_thresholds (the optional Gaussian, the Sobel and the magnitude histogram in one
//   pass; the workgroup that finishes last chooses the thresholds) -> nms_edge_sign (non-maximum
//   suppression, and the sign class of every pixel it keeps) -> hysteresis (edge tracking to its
//   fixed point in one workgroup; the classes of the weak pixels it drops are cleared),
// bit-identical to the scalar kernels (every step is integer; see shaders/*.comp for each
// kernel's contract and data layout).
//
// Per frame: the host writes the frame, with replicated borders, straight into a host-visible
// storage buffer and submits a command buffer recorded once for the frame size and options (a
// fill, the three dispatches, a barrier after each); the shaders write dx, dy and the edge map
// straight into host-visible buffers, and the host copies their rows out. One submit and one
// fence wait per frame; no staging copies. Thresholds are chosen on the device (the 64-bit
// product of the scalar rule is folded into a host-side push constant).
// On lavapipe the fixed cost per frame is the dispatches (each wakes the driver's worker threads)
// and the device timestamps (as costly as a dispatch each, so off unless asked for); the command
// recording and the copies of a small frame hardly count (docs/vulkan.md).
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
  // kUnavailable with the reason when there is no Vulkan loader or usable device.
  static Status Create(std::unique_ptr<VulkanEdgeStage>* out);
  ~VulkanEdgeStage();
  VulkanEdgeStage(const VulkanEdgeStage&) = delete;
  VulkanEdgeStage& operator=(const VulkanEdgeStage&) = delete;

  // dx, dy: width * height int16 each; edge_map: width * height bytes (0 none, 1 "+", 2 "-");
  // all row-major with stride = width. Same values as the scalar edge stage of runtime/detector.cc.
  Status Run(const ImageView& image, const Options& options, std::int16_t* dx, std::int16_t* dy,
             std::uint8_t* edge_map);

  // The steps (dispatches) the device time is split into (timestamps after each step's barrier).
  // kStepHysteresisBlocks takes no time on a device without the memory model (not dispatched).
  enum Step { kStepGaussianSobelThresholds, kStepNmsEdgeSign, kStepHysteresisBlocks, kStepHysteresis, kNumSteps };
  static const char* StepName(Step s);

  // Device timestamps around each step: off by default, because on lavapipe each timestamp costs
  // about as much as a dispatch (docs/vulkan.md). Takes effect at the next Run.
  void set_timing(bool on) { timing_ = on; }
  // Passes of hysteresis_blocks.comp before the one-workgroup hysteresis (same edge map, less
  // time on a GPU): -1 (default) one per 256 rows on a GPU, none on a CPU device such as lavapipe;
  // n >= 0 forces n (tests run the GPU's path on lavapipe). None without the memory model.
  // Takes effect at the next Run.
  void set_hysteresis_block_passes(int n) { block_passes_ = n < 0 ? -1 : n; }
  int hysteresis_block_passes(int height) const { return HysteresisBlockPasses(height); }
  // Device time of the last Run (GPU timestamps; the host's row copies into and out of the
  // host-visible buffers are not in it); -1 when step timing is off or the queue has no timestamps.
  double last_device_ms() const { return last_device_ms_; }
  // The same split by step (sums to last_device_ms() but for the fill command); -1 without
  // step timing.
  double last_step_device_ms(Step s) const { return last_step_ms_[s]; }
  const std::string& device_name() const { return ctx_->device_name(); }
  // The stage's Vulkan context, for another stage to share (VulkanArcStage::Create).
  const std::shared_ptr<VulkanContext>& context() const { return ctx_; }

 private:
  // kGaussianSobelThresholds blurs first, kSobelThresholds does not (BLUR = 1 / 0).
  // kHysteresisBlocks: only with the memory model (else a copy of kHysteresis, never dispatched).
  enum Pipeline {
    kGaussianSobelThresholds,
    kSobelThresholds,
    kNmsEdgeSign,
    kHysteresisBlocks,
    kHysteresis,
    kNumPipelines
  };
  static constexpr int kNumBindings = 7;

  // What the recorded command buffer was made for; Run re-records when the frame asks for other.
  struct Recording {
    int width = 0, height = 0;
    bool blur = false, timed = false;
    int block_passes = 0;  // hysteresis_blocks.comp dispatches
    // The thresholds' push constants (shaders/gaussian_sobel_thresholds.comp).
    std::uint32_t need = 0, low_permille = 0, min_high = 0, contrast_need = 0, contrast_ref = 0, noise_need = 0;
    std::uint32_t tile_shift = 0;  // kernels/canny_thresholds.h CannyTiles (the tiles follow from it and the size)
    bool operator==(const Recording&) const = default;
  };

  VulkanEdgeStage() = default;
  Status Init();
  Status Resize(int width, int height);
  void ReleaseFrameBuffers();
  void Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t gx, std::uint32_t gy, const std::uint32_t* push);
  void Dispatch1D(VkCommandBuffer cb, Pipeline p, std::uint64_t groups, const std::uint32_t* push);
  Status Record(const Recording& rec);
  int HysteresisBlockPasses(int height) const;

  std::shared_ptr<VulkanContext> ctx_;
  // Layouts, pipelines (indexed by Pipeline), the set, command buffer 0 (the frame's, recorded
  // once per Recording), fence, timestamps. Declared after ctx_, so it is released before it.
  VulkanProgram program_;

  // Bindings 0..6: image (packed u8, padded), dx (packed i16), dy, hist (bins + finished-group
  // count + tiles' maxima), thresholds (a pair per tile), masks, edges (packed u8); hist and
  // thresholds sized for the smallest tiles (kNmsMinTileShift). Host-visible, used in place (no staging):
  // image, dx, dy, edges.
  VulkanBuffer buffers_[kNumBindings];
  int width_ = 0, height_ = 0;
  Recording recorded_;  // width 0: nothing recorded
  bool timing_ = false;
  int block_passes_ = -1;
  std::uint32_t chunks_ = 0;           // 16-pixel chunks per row: ceil(width / 16)
  std::uint32_t padded_row_vec4_ = 0;  // uvec4 per row of the padded frame: chunks_ + 2
  std::uint32_t mask_words_ = 0;       // 32-pixel hysteresis mask words per row: ceil(width / 32)
  static constexpr std::uint32_t kPushWords = 14;
  double last_device_ms_ = -1;
  double last_step_ms_[kNumSteps] = {-1, -1, -1, -1};
};

}  // namespace ellipsekit
