// The Vulkan context: loader, instance, one physical device, one compute queue, a pipeline cache and
// the buffer helpers the compute stages share.
//
// The Vulkan loader is opened at run time (dlopen of libvulkan.so.1), so a build with Vulkan runs on
// machines without it: Create() then answers kUnavailable with the reason, and the caller falls back.
// Device choice: ELLIPSEKIT_VK_DEVICE (an index into the device list, or a case-insensitive
// substring of the device name) when set; otherwise the first discrete GPU, then integrated, then
// virtual, then CPU (lavapipe), among devices with Vulkan >= 1.1 and a compute queue.
// Pipeline cache: in memory; with ELLIPSEKIT_VK_PIPELINE_CACHE=<file> it starts from that file's
// contents (a missing, unreadable or foreign file is an empty start: the driver checks the header)
// and is written back there when the context is destroyed, through <file>.tmp and a rename, so the
// file is never left half-written; a failed write leaves the old file as it was.
#pragma once

#define VK_NO_PROTOTYPES
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "ellipsekit/types.h"

namespace ellipsekit {

// Every entry point the runtime uses, loaded from the loader at run time.
#define ELLIPSEKIT_VK_INSTANCE_FUNCTIONS(X)                                                         \
  X(vkDestroyInstance) X(vkEnumeratePhysicalDevices) X(vkGetPhysicalDeviceProperties)               \
  X(vkGetPhysicalDeviceQueueFamilyProperties) X(vkGetPhysicalDeviceMemoryProperties)                \
  X(vkCreateDevice) X(vkGetDeviceProcAddr) X(vkGetPhysicalDeviceFeatures)                           \
  X(vkGetPhysicalDeviceFeatures2) X(vkEnumerateDeviceExtensionProperties)
#define ELLIPSEKIT_VK_DEVICE_FUNCTIONS(X)                                                           \
  X(vkDestroyDevice) X(vkGetDeviceQueue) X(vkCreateBuffer) X(vkDestroyBuffer)                       \
  X(vkGetBufferMemoryRequirements) X(vkAllocateMemory) X(vkFreeMemory) X(vkBindBufferMemory)        \
  X(vkMapMemory) X(vkUnmapMemory) X(vkFlushMappedMemoryRanges) X(vkInvalidateMappedMemoryRanges)    \
  X(vkCreateShaderModule) X(vkDestroyShaderModule) X(vkCreatePipelineCache)                         \
  X(vkDestroyPipelineCache) X(vkGetPipelineCacheData) X(vkCreateComputePipelines) X(vkDestroyPipeline)                        \
  X(vkCreatePipelineLayout) X(vkDestroyPipelineLayout) X(vkCreateDescriptorSetLayout)               \
  X(vkDestroyDescriptorSetLayout) X(vkCreateDescriptorPool) X(vkDestroyDescriptorPool)              \
  X(vkAllocateDescriptorSets) X(vkUpdateDescriptorSets) X(vkCreateCommandPool)                      \
  X(vkDestroyCommandPool) X(vkAllocateCommandBuffers) X(vkResetCommandBuffer)                       \
  X(vkBeginCommandBuffer) X(vkEndCommandBuffer) X(vkCmdBindPipeline) X(vkCmdBindDescriptorSets)     \
  X(vkCmdPushConstants) X(vkCmdDispatch) X(vkCmdPipelineBarrier) X(vkCmdCopyBuffer)                 \
  X(vkCmdFillBuffer) X(vkCmdWriteTimestamp) X(vkCmdResetQueryPool) X(vkCreateQueryPool)             \
  X(vkDestroyQueryPool) X(vkGetQueryPoolResults) X(vkQueueSubmit) X(vkCreateFence)                  \
  X(vkDestroyFence) X(vkWaitForFences) X(vkResetFences) X(vkDeviceWaitIdle)

struct VulkanFunctions {
#define ELLIPSEKIT_VK_DECLARE(name) PFN_##name name = nullptr;
  ELLIPSEKIT_VK_DECLARE(vkGetInstanceProcAddr)
  ELLIPSEKIT_VK_DECLARE(vkCreateInstance)
  ELLIPSEKIT_VK_DECLARE(vkEnumerateInstanceVersion)
  ELLIPSEKIT_VK_INSTANCE_FUNCTIONS(ELLIPSEKIT_VK_DECLARE)
  ELLIPSEKIT_VK_DEVICE_FUNCTIONS(ELLIPSEKIT_VK_DECLARE)
#undef ELLIPSEKIT_VK_DECLARE
};

// A buffer with its own memory allocation; `mapped` is set for host-visible buffers.
struct VulkanBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;
  bool coherent = true;
};

class VulkanContext {
 public:
  // kUnavailable (with the reason) when there is no loader, no instance or no suitable device.
  static Status Create(std::unique_ptr<VulkanContext>* out);
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  const VulkanFunctions& vk() const { return vk_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  VkPipelineCache pipeline_cache() const { return pipeline_cache_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const std::string& device_name() const { return device_name_; }
  // Nanoseconds per timestamp tick; 0 when the compute queue has no timestamps.
  double timestamp_period_ns() const { return timestamp_period_ns_; }
  std::uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }
  // True when the device was created with the shaderInt64 feature (the arc-stage shaders need
  // 64-bit integers; the edge stage does not). Enabled whenever the device offers it.
  bool shader_int64() const { return shader_int64_; }
  // True when the device was created with the vulkanMemoryModel and vulkanMemoryModelDeviceScope
  // features of VK_KHR_vulkan_memory_model (mandatory in Vulkan 1.3), so shaders may use
  // relaxed atomic loads and stores.
  // ELLIPSEKIT_VK_NO_MEMORY_MODEL=1 leaves it off, to test the fallback shaders.
  bool memory_model() const { return memory_model_; }

  // Storage buffer usable as copy source and destination. host_visible: mapped, host-coherent
  // when the device offers it (otherwise Flush/Invalidate below do the work).
  Status CreateBuffer(VkDeviceSize size, bool host_visible, VulkanBuffer* out);
  void DestroyBuffer(VulkanBuffer* buffer);
  void FlushHostWrites(const VulkanBuffer& buffer);
  void InvalidateForHostReads(const VulkanBuffer& buffer);

 private:
  VulkanContext() = default;
  Status Init();

  void* library_ = nullptr;
  VulkanFunctions vk_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkPipelineCache pipeline_cache_ = VK_NULL_HANDLE;
  std::string pipeline_cache_file_;  // ELLIPSEKIT_VK_PIPELINE_CACHE, "" when unset
  std::string device_name_;
  double timestamp_period_ns_ = 0;
  std::uint32_t timestamp_valid_bits_ = 0;
  bool shader_int64_ = false;
  bool memory_model_ = false;
};

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" and so on, for messages.
const char* VkResultName(VkResult r);

}  // namespace ellipsekit
