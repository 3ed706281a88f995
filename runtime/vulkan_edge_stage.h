// The edge stage on a Vulkan compute device: gaussian? -> sobel -> histogram -> thresholds -> nms
// -> hysteresis -> edge_sign, bit-identical to the scalar kernels (every step is integer; see
// shaders/*.comp for each kernel's contract).
//
// Per frame: the frame is copied into a host-visible staging buffer, and one command buffer does
// upload -> all stages (with a barrier after each) -> kRoundsPerSubmit hysteresis rounds ->
// edge_sign -> download of dx, dy and the edge map into a staging buffer. Thresholds are chosen on
// the device (the 64-bit product of the scalar rule is folded into a host-side push constant).
// Hysteresis: the host reads the device-side "last round changed something" flag after the
// submit; while it is set, a second command buffer with kRoundsPerSubmit more rounds + edge_sign +
// edge-map download is submitted (most frames need none: a round floods whole 16x16 tiles).
// The number of rounds is bounded by width * height + 1 (each non-final round promotes a pixel).
//
// Buffers, descriptor set and command buffers are made for one frame size and reused; a new size
// re-creates them. Pipelines are created once, through the context's pipeline cache. Storage is
// 32-bit words only (bytes and int16 packed in the shaders), so only core Vulkan 1.1 is needed.
// Not thread-safe: one thread at a time per instance (like a Detector).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "ellipsekit/options.h"
#include "ellipsekit/types.h"
#include "runtime/vulkan_context.h"

namespace ellipsekit {

class VulkanEdgeStage {
 public:
  static constexpr int kRoundsPerSubmit = 8;

  // kUnavailable with the reason when there is no Vulkan loader or usable device.
  static Status Create(std::unique_ptr<VulkanEdgeStage>* out);
  ~VulkanEdgeStage();
  VulkanEdgeStage(const VulkanEdgeStage&) = delete;
  VulkanEdgeStage& operator=(const VulkanEdgeStage&) = delete;

  // dx, dy: width * height int16 each; edge_map: width * height bytes (0 none, 1 "+", 2 "-");
  // all row-major with stride = width. Same values as the scalar edge stage of runtime/detector.cc.
  Status Run(const ImageView& image, const Options& options, std::int16_t* dx, std::int16_t* dy,
             std::uint8_t* edge_map);

  // Device time of the last Run (GPU timestamps, all submits summed, transfers included);
  // -1 when the queue has no timestamps.
  double last_device_ms() const { return last_device_ms_; }
  // Hysteresis rounds the last Run recorded (multiples of kRoundsPerSubmit).
  int last_hysteresis_rounds() const { return last_rounds_; }
  const std::string& device_name() const { return ctx_->device_name(); }

 private:
  enum Pipeline { kGaussian, kSobel, kHistogram, kSelect, kNms, kHysteresis, kEdgeSign, kNumPipelines };
  static constexpr int kNumBindings = 10;

  VulkanEdgeStage() = default;
  Status Init();
  Status Resize(int width, int height);
  void ReleaseFrameBuffers();
  void Dispatch(VkCommandBuffer cb, Pipeline p, std::uint32_t gx, std::uint32_t gy, const std::uint32_t* push);
  void Dispatch1D(VkCommandBuffer cb, Pipeline p, std::uint64_t groups, const std::uint32_t* push);
  void Barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
               VkAccessFlags dst_access);
  void RecordHysteresisAndOutput(VkCommandBuffer cb, bool download_gradients);
  Status Submit(VkCommandBuffer cb);

  std::unique_ptr<VulkanContext> ctx_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  VkPipeline pipelines_[kNumPipelines] = {};
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer frame_cb_ = VK_NULL_HANDLE, more_rounds_cb_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool query_pool_ = VK_NULL_HANDLE;

  // Bindings 0..9: image (packed u8), blurred, dx (packed i16), dy, mag, hist, thresholds, map,
  // flags (host-visible), edges (packed u8). Staging: upload (image), download (dx | dy | edges).
  VulkanBuffer buffers_[kNumBindings];
  VulkanBuffer upload_, download_;
  VkDeviceSize dx_bytes_ = 0, edge_bytes_ = 0;
  int width_ = 0, height_ = 0;
  std::uint32_t push_[6] = {};
  double last_device_ms_ = -1;
  int last_rounds_ = 0;
};

}  // namespace ellipsekit
