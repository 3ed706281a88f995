// VulkanProgram: the fixed Vulkan objects one compute stage needs, made once and released together.
//
// Contract:
// - Create(ctx, num_bindings, push_constant_bytes, shaders, num_shaders) makes, on ctx's device:
//   a descriptor set layout of `num_bindings` storage buffers (bindings 0..num_bindings-1, compute
//   stage), a pipeline layout with that set and one compute push-constant range of
//   `push_constant_bytes` at offset 0, one compute pipeline per shader (entry point "main", through
//   ctx's pipeline cache; a shader with `specialized` set gets constant_id 0 = `constant0`), a
//   descriptor pool holding exactly one set (allocated), a resettable command pool on ctx's queue
//   family with two primary command buffers, an unsignalled fence, and, when the queue has
//   timestamps, a kMaxTimestamps-query timestamp pool (timed() is false otherwise).
//   On failure it answers kInternal naming the failing call; what was made is released by the
//   destructor. Call it once per object.
// - The helpers below allocate nothing and may be used on the per-frame path.
// - ctx must outlive the program; the owner waits for the device to be idle (and releases the
//   buffers bound to the set) before destroying it. The destructor releases every object made.
// - Not thread-safe: one thread at a time (like the stages that own it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ellipsekit/types.h"
#include "runtime/vulkan_context.h"

namespace ellipsekit {

// "<what> failed: VK_ERROR_..." as a kInternal Status.
Status VulkanFailure(const char* what, VkResult r);

class VulkanProgram {
 public:
  struct Shader {
    const std::uint32_t* code;  // SPIR-V words
    std::size_t bytes;
    bool specialized = false;   // set constant_id 0 to constant0
    std::uint32_t constant0 = 0;
  };
  static constexpr int kMaxBindings = 16;
  static constexpr int kMaxTimestamps = 8;

  VulkanProgram() = default;
  ~VulkanProgram();
  VulkanProgram(const VulkanProgram&) = delete;
  VulkanProgram& operator=(const VulkanProgram&) = delete;

  Status Create(VulkanContext* ctx, int num_bindings, std::uint32_t push_constant_bytes, const Shader* shaders,
                int num_shaders);

  VkPipeline pipeline(int i) const { return pipelines_[static_cast<std::size_t>(i)]; }
  VkPipelineLayout layout() const { return pipeline_layout_; }
  VkDescriptorSet set() const { return set_; }
  VkCommandBuffer command_buffer(int i) const { return cbs_[i]; }
  VkFence fence() const { return fence_; }
  // Whether the queue has timestamps (then the helpers below record and read them).
  bool timed() const { return query_pool_ != VK_NULL_HANDLE; }

  // Points binding b of the set at the whole of buffers[b], for b < num_bindings.
  void BindBuffers(const VulkanBuffer* buffers);
  // Binds pipeline i and the set, pushes `push_bytes` of `push`, and dispatches gx x gy x 1 groups.
  void Dispatch(VkCommandBuffer cb, int i, std::uint32_t push_bytes, const void* push, std::uint32_t gx,
                std::uint32_t gy);
  // One global memory barrier.
  void Barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
               VkAccessFlags dst_access);
  // Submits the (ended) cb to the queue and waits on the fence (reset afterwards).
  Status SubmitAndWait(VkCommandBuffer cb);
  // Resets queries [first, first + count) and writes query `first` at the top of the pipe: the start
  // of a timed span. Records nothing without timestamps.
  void StartTimestamps(VkCommandBuffer cb, int first, int count);
  // Writes query `query` once the work recorded before it is done. Records nothing without
  // timestamps.
  void Timestamp(VkCommandBuffer cb, int query);
  // Adds the time between queries 0 and 1 to *device_ms (nothing when there are no timestamps or
  // the results are not available).
  void AddDeviceMs(double* device_ms) { AddIntervalsMs(0, 1, device_ms); }
  // Adds the time between queries first + i and first + i + 1 to ms[i], for i < count (queries
  // first .. first + count < kMaxTimestamps, all written by the last submit; nothing when there
  // are no timestamps or the results are not available).
  void AddIntervalsMs(int first, int count, double* ms);

 private:
  VulkanContext* ctx_ = nullptr;
  int num_bindings_ = 0;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  std::vector<VkPipeline> pipelines_;
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cbs_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool query_pool_ = VK_NULL_HANDLE;
};

}  // namespace ellipsekit
