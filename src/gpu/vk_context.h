// The headless Vulkan context: instance (validation layers when HYBRIDBENCH_VALIDATION=1), one
// physical device chosen by index or name substring, one graphics+compute queue, a command pool,
// and the ray-tracing extensions the device offers. No surface, no swapchain.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace hb {

// Throws DeviceError naming the call and its VkResult when result is not VK_SUCCESS.
void vkCheck(VkResult result, const char* call);
#define VK_CHECK(call) ::hb::vkCheck((call), #call)
const char* vkResultName(VkResult r);

// HYBRIDBENCH_GPU_TIMEOUT_S (default 300): how long VulkanContext::submitAndWait waits for one
// submission. Throws InputError when it is not a number > 0.
double gpuTimeoutSeconds();

struct DeviceInfo {
  uint32_t index = 0;
  std::string name;
  std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
  uint32_t vendorId = 0, deviceId = 0;
  std::string vendor;  // "NVIDIA", "AMD", "Intel", "Mesa (lavapipe)", ...
  std::string driverName, driverInfo, driverVersion;
  std::string apiVersion;
  std::string uuid;
  bool accelerationStructure = false;
  bool rayQuery = false;
  bool rayTracingPipeline = false;
  bool timestamps = false;
  bool bufferInt64Atomics = false;  // set by VulkanContext (the device actually opened)
  bool shaderFloat64 = false;
  bool fragmentSubgroupBallot = false;  // ballot and arithmetic subgroup operations in fragment shaders
  bool computeSubgroupBallot = false;   // ballot subgroup operations in compute shaders
  // VK_KHR_pipeline_executable_properties: what the driver compiled a pipeline into (registers,
  // spills, ...; gpu/vk_pipeline.h pipelineStatistics). Set by VulkanContext (the device opened).
  bool pipelineStatistics = false;
  uint32_t timestampValidBits = 0;
  double timestampPeriodNs = 0;
  std::string rtBackends() const;  // "rayquery+pipeline", "pipeline", "none"
};

// Every physical device (creates a throwaway instance). Never throws for a device that lacks
// features; throws DeviceError when there is no Vulkan at all.
std::vector<DeviceInfo> enumerateDevices();

// Resolves a --device argument: an index, or a case-insensitive substring of the name. Throws
// InputError (one line listing the devices) when nothing matches or the index does not exist.
uint32_t resolveDevice(const std::vector<DeviceInfo>& devices, const std::string& selector);

struct RtFunctions {
  PFN_vkCreateAccelerationStructureKHR createAccelerationStructure = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroyAccelerationStructure = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR getBuildSizes = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmdBuild = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR getAddress = nullptr;
  PFN_vkCreateRayTracingPipelinesKHR createRayTracingPipelines = nullptr;
  PFN_vkGetRayTracingShaderGroupHandlesKHR getShaderGroupHandles = nullptr;
  PFN_vkCmdTraceRaysKHR cmdTraceRays = nullptr;
};

class VulkanContext {
 public:
  // deviceIndex must come from resolveDevice. Validation follows HYBRIDBENCH_VALIDATION unless forced.
  explicit VulkanContext(uint32_t deviceIndex);
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  const DeviceInfo& info() const { return info_; }
  const RtFunctions& rt() const { return rt_; }
  // VK_KHR_pipeline_executable_properties' queries; null unless info().pipelineStatistics.
  PFN_vkGetPipelineExecutablePropertiesKHR getExecutableProperties = nullptr;
  PFN_vkGetPipelineExecutableStatisticsKHR getExecutableStatistics = nullptr;
  const VkPhysicalDeviceProperties& properties() const { return props_; }
  const VkPhysicalDeviceRayTracingPipelinePropertiesKHR& rtPipelineProps() const { return rtProps_; }
  bool canTrace() const { return info_.rayQuery || info_.rayTracingPipeline; }
  bool validationEnabled() const { return validation_; }
  uint32_t validationMessages() const { return validationMessages_.load(); }

  // Records with fn into a fresh primary command buffer, submits, waits. Throws DeviceError.
  // Records fn into a one-time command buffer, submits it and waits for it, at most
  // HYBRIDBENCH_GPU_TIMEOUT_S seconds (default 300). Past that the device may be hung and nothing
  // may touch it again (freeing what it still uses crashes some drivers): one line on stderr names
  // `what`, and the process ends at once with exit 3. What is written stays written (a sweep
  // writes its files after every variant; --resume reruns the rest).
  void submitAndWait(const std::function<void(VkCommandBuffer)>& fn, const char* what = "a GPU submission") const;

  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags flags) const;

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                      VkDebugUtilsMessageTypeFlagsEXT,
                                                      const VkDebugUtilsMessengerCallbackDataEXT*, void*);
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  double timeoutSeconds_ = 300.0;
  DeviceInfo info_;
  RtFunctions rt_;
  VkPhysicalDeviceProperties props_{};
  VkPhysicalDeviceMemoryProperties memProps_{};
  VkPhysicalDeviceRayTracingPipelinePropertiesKHR rtProps_{};
  bool validation_ = false;
  mutable std::atomic<uint32_t> validationMessages_{0};
};

bool validationRequested();  // HYBRIDBENCH_VALIDATION=1

}  // namespace hb
