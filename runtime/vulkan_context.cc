#include "runtime/vulkan_context.h"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace ellipsekit {

namespace {

Status Unavailable(const std::string& why) { return {StatusCode::kUnavailable, "Vulkan unavailable: " + why}; }

// The whole file, or nothing when it cannot be read.
std::vector<char> ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return std::vector<char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Writes `bytes` to path.tmp, then renames it over path; on any failure path is untouched.
void WriteFileAtomically(const std::string& path, const std::vector<char>& bytes) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return;
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      return;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) std::remove(tmp.c_str());
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Preference order of device types: discrete, integrated, virtual, CPU, other.
int TypeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

// Keeps the driver that serves `device_function` (a pointer vkGetDeviceProcAddr returned, so it
// lies in the driver or in a layer) loaded for the rest of the process. The loader otherwise
// unloads the driver with the last instance, and loads it again with the next: for lavapipe that
// means re-initialising LLVM for every Detector. It also keeps the driver's static allocations
// reachable, so LeakSanitizer does not report them as leaks from an unknown (unloaded) module.
void PinDriver(void* device_function) {
  Dl_info info{};
  if (device_function == nullptr || dladdr(device_function, &info) == 0 || info.dli_fname == nullptr) return;
  // RTLD_NOLOAD: only takes a reference to the already loaded module; RTLD_NODELETE: never unload it.
  dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

}  // namespace

const char* VkResultName(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    default: return "VkResult error";
  }
}

Status VulkanContext::Create(std::unique_ptr<VulkanContext>* out) {
  std::unique_ptr<VulkanContext> ctx(new VulkanContext());
  Status st = ctx->Init();
  if (!st.ok()) return st;
  *out = std::move(ctx);
  return Status::Ok();
}

Status VulkanContext::Init() {
  library_ = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
  if (library_ == nullptr) library_ = dlopen("libvulkan.so", RTLD_NOW | RTLD_LOCAL);
  if (library_ == nullptr) return Unavailable("the Vulkan loader (libvulkan.so.1) is not installed");
  vk_.vkGetInstanceProcAddr = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library_, "vkGetInstanceProcAddr"));
  if (vk_.vkGetInstanceProcAddr == nullptr) return Unavailable("libvulkan.so.1 has no vkGetInstanceProcAddr");
  vk_.vkCreateInstance = reinterpret_cast<PFN_vkCreateInstance>(vk_.vkGetInstanceProcAddr(nullptr, "vkCreateInstance"));
  vk_.vkEnumerateInstanceVersion =
      reinterpret_cast<PFN_vkEnumerateInstanceVersion>(vk_.vkGetInstanceProcAddr(nullptr, "vkEnumerateInstanceVersion"));
  if (vk_.vkCreateInstance == nullptr) return Unavailable("the loader has no vkCreateInstance");
  std::uint32_t loader_version = VK_API_VERSION_1_0;
  if (vk_.vkEnumerateInstanceVersion != nullptr) vk_.vkEnumerateInstanceVersion(&loader_version);
  if (loader_version < VK_API_VERSION_1_1) return Unavailable("the Vulkan loader supports only Vulkan 1.0 (1.1 needed)");

  VkApplicationInfo app{};

  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "ellipsekit";
  app.pEngineName = "ellipsekit";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo ici{};
  ici.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ici.pApplicationInfo = &app;
  VkResult r = vk_.vkCreateInstance(&ici, nullptr, &instance_);
  if (r != VK_SUCCESS) return Unavailable(std::string("vkCreateInstance failed: ") + VkResultName(r));
#define ELLIPSEKIT_VK_LOAD_INSTANCE(name)                                                  \
  vk_.name = reinterpret_cast<PFN_##name>(vk_.vkGetInstanceProcAddr(instance_, #name)); \
  if (vk_.name == nullptr) return Unavailable("the loader has no " #name);
  ELLIPSEKIT_VK_INSTANCE_FUNCTIONS(ELLIPSEKIT_VK_LOAD_INSTANCE)
#undef ELLIPSEKIT_VK_LOAD_INSTANCE

  std::uint32_t count = 0;
  r = vk_.vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  if (r != VK_SUCCESS || count == 0) return Unavailable("no Vulkan physical device (no GPU driver or ICD installed)");
  std::vector<VkPhysicalDevice> devices(count);
  vk_.vkEnumeratePhysicalDevices(instance_, &count, devices.data());
  devices.resize(count);

  // Candidates: Vulkan >= 1.1 with a compute queue family.
  struct Candidate {
    int index;
    VkPhysicalDevice device;
    VkPhysicalDeviceProperties props;
    std::uint32_t family;
    std::uint32_t timestamp_bits;
  };
  std::vector<Candidate> usable;
  std::string listing;
  for (std::uint32_t i = 0; i < count; ++i) {
    VkPhysicalDeviceProperties p;
    vk_.vkGetPhysicalDeviceProperties(devices[i], &p);
    listing += (listing.empty() ? "" : ", ") + std::to_string(i) + ": " + p.deviceName;
    if (p.apiVersion < VK_API_VERSION_1_1) continue;
    std::uint32_t nf = 0;
    vk_.vkGetPhysicalDeviceQueueFamilyProperties(devices[i], &nf, nullptr);
    std::vector<VkQueueFamilyProperties> families(nf);
    vk_.vkGetPhysicalDeviceQueueFamilyProperties(devices[i], &nf, families.data());
    // Prefer a compute-only family (async compute), else any with compute.
    int best = -1;
    for (std::uint32_t f = 0; f < nf; ++f) {
      if (!(families[f].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
      if (best < 0 || !(families[f].queueFlags & VK_QUEUE_GRAPHICS_BIT)) best = static_cast<int>(f);
    }
    if (best < 0) continue;
    usable.push_back({static_cast<int>(i), devices[i], p, static_cast<std::uint32_t>(best),
                      families[best].timestampValidBits});
  }
  if (usable.empty()) return Unavailable("no Vulkan 1.1 device with a compute queue among [" + listing + "]");

  const Candidate* chosen = nullptr;
  if (const char* env = std::getenv("ELLIPSEKIT_VK_DEVICE"); env != nullptr && *env != '\0') {
    const std::string want(env);
    const bool numeric = std::all_of(want.begin(), want.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
    for (const Candidate& c : usable) {
      if (numeric ? c.index == std::atoi(env) : Lower(c.props.deviceName).find(Lower(want)) != std::string::npos) {
        chosen = &c;
        break;
      }
    }
    if (chosen == nullptr)
      return Unavailable("ELLIPSEKIT_VK_DEVICE='" + want + "' matches no usable device among [" + listing + "]");
  } else {
    chosen = &*std::min_element(usable.begin(), usable.end(), [](const Candidate& a, const Candidate& b) {
      return TypeRank(a.props.deviceType) < TypeRank(b.props.deviceType);
    });
  }
  physical_ = chosen->device;
  properties_ = chosen->props;
  device_name_ = chosen->props.deviceName;
  queue_family_ = chosen->family;
  timestamp_valid_bits_ = chosen->timestamp_bits;
  timestamp_period_ns_ = timestamp_valid_bits_ != 0 ? chosen->props.limits.timestampPeriod : 0.0;
  vk_.vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{};
  qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qci.queueFamilyIndex = queue_family_;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  // shaderInt64 when offered (runtime/vulkan_arc_stage.h needs it; a device without it still runs
  // the edge stage, and the arc stage reports kUnavailable).
  VkPhysicalDeviceFeatures offered{}, enabled{};
  vk_.vkGetPhysicalDeviceFeatures(physical_, &offered);
  enabled.shaderInt64 = offered.shaderInt64;
  shader_int64_ = offered.shaderInt64 == VK_TRUE;
  dci.pEnabledFeatures = &enabled;
  // vulkanMemoryModel when offered. The instance asks for Vulkan 1.1, where it is the extension
  // VK_KHR_vulkan_memory_model (core only from 1.2), so the extension is always what is enabled.
  VkPhysicalDeviceVulkanMemoryModelFeatures memory_model{};
  memory_model.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_MEMORY_MODEL_FEATURES;
  const char* memory_model_extension = VK_KHR_VULKAN_MEMORY_MODEL_EXTENSION_NAME;
  auto has_extension = [&](const char* name) {
    std::uint32_t n = 0;
    if (vk_.vkEnumerateDeviceExtensionProperties(physical_, nullptr, &n, nullptr) != VK_SUCCESS) return false;
    std::vector<VkExtensionProperties> ext(n);
    if (vk_.vkEnumerateDeviceExtensionProperties(physical_, nullptr, &n, ext.data()) != VK_SUCCESS) return false;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (std::string(ext[i].extensionName) == name) return true;
    }
    return false;
  };
  const char* no_memory_model = std::getenv("ELLIPSEKIT_VK_NO_MEMORY_MODEL");
  if ((no_memory_model == nullptr || std::string(no_memory_model) != "1") &&
      has_extension(memory_model_extension)) {
    VkPhysicalDeviceFeatures2 features2{};
    features2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features2.pNext = &memory_model;
    vk_.vkGetPhysicalDeviceFeatures2(physical_, &features2);
    // Device scope too: with the memory model enabled, the other shaders' default (Device-scope)
    // atomics are valid only when vulkanMemoryModelDeviceScope is enabled as well.
    memory_model_ = memory_model.vulkanMemoryModel == VK_TRUE && memory_model.vulkanMemoryModelDeviceScope == VK_TRUE;
  }
  if (memory_model_) {
    memory_model = {};
    memory_model.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_MEMORY_MODEL_FEATURES;
    memory_model.vulkanMemoryModel = VK_TRUE;
    memory_model.vulkanMemoryModelDeviceScope = VK_TRUE;
    dci.pNext = &memory_model;
    dci.enabledExtensionCount = 1;
    dci.ppEnabledExtensionNames = &memory_model_extension;
  }
  r = vk_.vkCreateDevice(physical_, &dci, nullptr, &device_);
  if (r != VK_SUCCESS) return Unavailable("vkCreateDevice on '" + device_name_ + "' failed: " + VkResultName(r));
#define ELLIPSEKIT_VK_LOAD_DEVICE(name)                                                 \
  vk_.name = reinterpret_cast<PFN_##name>(vk_.vkGetDeviceProcAddr(device_, #name));    \
  if (vk_.name == nullptr) return Unavailable("the device has no " #name);
  ELLIPSEKIT_VK_DEVICE_FUNCTIONS(ELLIPSEKIT_VK_LOAD_DEVICE)
#undef ELLIPSEKIT_VK_LOAD_DEVICE
  PinDriver(reinterpret_cast<void*>(vk_.vkCmdDispatch));
  vk_.vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

  VkPipelineCacheCreateInfo pcci{};
  pcci.sType = VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO;
  std::vector<char> initial;
  if (const char* file = std::getenv("ELLIPSEKIT_VK_PIPELINE_CACHE"); file != nullptr && *file != '\0') {
    pipeline_cache_file_ = file;
    initial = ReadFileBytes(pipeline_cache_file_);
    pcci.initialDataSize = initial.size();
    pcci.pInitialData = initial.empty() ? nullptr : initial.data();
  }
  r = vk_.vkCreatePipelineCache(device_, &pcci, nullptr, &pipeline_cache_);
  if (r != VK_SUCCESS && pcci.initialDataSize != 0) {  // data the driver would not take: start empty
    pcci.initialDataSize = 0;
    pcci.pInitialData = nullptr;
    r = vk_.vkCreatePipelineCache(device_, &pcci, nullptr, &pipeline_cache_);
  }
  if (r != VK_SUCCESS) return {StatusCode::kInternal, std::string("vkCreatePipelineCache failed: ") + VkResultName(r)};
  return Status::Ok();
}

VulkanContext::~VulkanContext() {
  if (device_ != VK_NULL_HANDLE) {
    vk_.vkDeviceWaitIdle(device_);
    if (pipeline_cache_ != VK_NULL_HANDLE && !pipeline_cache_file_.empty()) {
      std::size_t size = 0;
      if (vk_.vkGetPipelineCacheData(device_, pipeline_cache_, &size, nullptr) == VK_SUCCESS && size > 0) {
        std::vector<char> bytes(size);
        if (vk_.vkGetPipelineCacheData(device_, pipeline_cache_, &size, bytes.data()) == VK_SUCCESS) {
          bytes.resize(size);
          WriteFileAtomically(pipeline_cache_file_, bytes);
        }
      }
    }
    if (pipeline_cache_ != VK_NULL_HANDLE) vk_.vkDestroyPipelineCache(device_, pipeline_cache_, nullptr);
    vk_.vkDestroyDevice(device_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE && vk_.vkDestroyInstance != nullptr) vk_.vkDestroyInstance(instance_, nullptr);
  if (library_ != nullptr) dlclose(library_);
}

Status VulkanContext::CreateBuffer(VkDeviceSize size, bool host_visible, VulkanBuffer* out) {
  *out = VulkanBuffer{};
  size = std::max<VkDeviceSize>(size, 4);
  VkBufferCreateInfo bci{};
  bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  bci.size = size;
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkResult r = vk_.vkCreateBuffer(device_, &bci, nullptr, &out->buffer);
  if (r != VK_SUCCESS) return {StatusCode::kInternal, std::string("vkCreateBuffer failed: ") + VkResultName(r)};
  out->size = size;
  VkMemoryRequirements req;
  vk_.vkGetBufferMemoryRequirements(device_, out->buffer, &req);
  // Host-visible: prefer coherent (+ cached for readback); device-local otherwise.
  const VkMemoryPropertyFlags wants[2][2] = {
      {VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0},
      {VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT}};
  int type = -1;
  for (VkMemoryPropertyFlags want : wants[host_visible ? 1 : 0]) {
    for (std::uint32_t t = 0; t < memory_.memoryTypeCount && type < 0; ++t) {
      if ((req.memoryTypeBits & (1u << t)) && (memory_.memoryTypes[t].propertyFlags & want) == want) type = static_cast<int>(t);
    }
    if (type >= 0) break;
  }
  if (type < 0) {
    DestroyBuffer(out);
    return {StatusCode::kInternal, "no Vulkan memory type fits a storage buffer"};
  }
  VkMemoryAllocateInfo mai{};
  mai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = static_cast<std::uint32_t>(type);
  r = vk_.vkAllocateMemory(device_, &mai, nullptr, &out->memory);
  if (r != VK_SUCCESS) {
    DestroyBuffer(out);
    return {StatusCode::kInternal, std::string("vkAllocateMemory failed: ") + VkResultName(r)};
  }
  vk_.vkBindBufferMemory(device_, out->buffer, out->memory, 0);
  if (host_visible) {
    out->coherent = (memory_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    r = vk_.vkMapMemory(device_, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped);
    if (r != VK_SUCCESS) {
      DestroyBuffer(out);
      return {StatusCode::kInternal, std::string("vkMapMemory failed: ") + VkResultName(r)};
    }
  }
  return Status::Ok();
}

void VulkanContext::DestroyBuffer(VulkanBuffer* b) {
  if (b->mapped != nullptr) vk_.vkUnmapMemory(device_, b->memory);
  if (b->buffer != VK_NULL_HANDLE) vk_.vkDestroyBuffer(device_, b->buffer, nullptr);
  if (b->memory != VK_NULL_HANDLE) vk_.vkFreeMemory(device_, b->memory, nullptr);
  *b = VulkanBuffer{};
}

void VulkanContext::FlushHostWrites(const VulkanBuffer& b) {
  if (b.coherent || b.mapped == nullptr) return;
  VkMappedMemoryRange range{};
  range.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE;
  range.memory = b.memory;
  range.size = VK_WHOLE_SIZE;
  vk_.vkFlushMappedMemoryRanges(device_, 1, &range);
}

void VulkanContext::InvalidateForHostReads(const VulkanBuffer& b) {
  if (b.coherent || b.mapped == nullptr) return;
  VkMappedMemoryRange range{};
  range.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE;
  range.memory = b.memory;
  range.size = VK_WHOLE_SIZE;
  vk_.vkInvalidateMappedMemoryRanges(device_, 1, &range);
}

}  // namespace ellipsekit
