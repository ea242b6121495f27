#include "gpu/vk_context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>

#include "base/errors.h"
#include "base/text_format.h"

namespace hb {

const char* vkResultName(VkResult r) {
  switch (r) {
#define HB_CASE(x) \
  case x: return #x
    HB_CASE(VK_SUCCESS);
    HB_CASE(VK_NOT_READY);
    HB_CASE(VK_TIMEOUT);
    HB_CASE(VK_INCOMPLETE);
    HB_CASE(VK_ERROR_OUT_OF_HOST_MEMORY);
    HB_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY);
    HB_CASE(VK_ERROR_INITIALIZATION_FAILED);
    HB_CASE(VK_ERROR_DEVICE_LOST);
    HB_CASE(VK_ERROR_MEMORY_MAP_FAILED);
    HB_CASE(VK_ERROR_LAYER_NOT_PRESENT);
    HB_CASE(VK_ERROR_EXTENSION_NOT_PRESENT);
    HB_CASE(VK_ERROR_FEATURE_NOT_PRESENT);
    HB_CASE(VK_ERROR_INCOMPATIBLE_DRIVER);
    HB_CASE(VK_ERROR_TOO_MANY_OBJECTS);
    HB_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED);
    HB_CASE(VK_ERROR_FRAGMENTED_POOL);
    HB_CASE(VK_ERROR_OUT_OF_POOL_MEMORY);
    HB_CASE(VK_ERROR_UNKNOWN);
#undef HB_CASE
    default: return "VkResult(unknown)";
  }
}

void vkCheck(VkResult result, const char* call) {
  if (result != VK_SUCCESS)
    throw DeviceError(std::string(call) + " failed: " + vkResultName(result) + " (" + std::to_string(result) + ")");
}

bool validationRequested() {
  const char* v = std::getenv("HYBRIDBENCH_VALIDATION");
  return v && std::string(v) == "1";
}

std::string DeviceInfo::rtBackends() const {
  if (!accelerationStructure) return "none";
  if (rayQuery && rayTracingPipeline) return "rayquery+pipeline";
  if (rayQuery) return "rayquery";
  if (rayTracingPipeline) return "pipeline";
  return "none";
}

static std::string versionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

static bool hasExtension(const std::vector<VkExtensionProperties>& exts, const char* name) {
  return std::any_of(exts.begin(), exts.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

static std::vector<VkExtensionProperties> deviceExtensions(VkPhysicalDevice pd) {
  uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
  return exts;
}

static uint32_t pickQueueFamily(VkPhysicalDevice pd, uint32_t* timestampBits) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
  for (uint32_t i = 0; i < n; ++i)
    if ((fams[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) && (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) {
      if (timestampBits) *timestampBits = fams[i].timestampValidBits;
      return i;
    }
  return UINT32_MAX;
}

static DeviceInfo describe(VkPhysicalDevice pd, uint32_t index) {
  VkPhysicalDeviceSubgroupProperties sg{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceIDProperties idProps{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES, &sg};
  VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES, &idProps};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &drv};
  vkGetPhysicalDeviceProperties2(pd, &p2);
  const VkPhysicalDeviceProperties& p = p2.properties;
  DeviceInfo d;
  d.index = index;
  d.name = p.deviceName;
  switch (p.deviceType) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: d.type = "discrete"; break;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: d.type = "integrated"; break;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: d.type = "virtual"; break;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: d.type = "cpu"; break;
    default: d.type = "other";
  }
  d.vendorId = p.vendorID;
  d.deviceId = p.deviceID;
  d.fragmentSubgroupBallot = (sg.supportedStages & VK_SHADER_STAGE_FRAGMENT_BIT) &&
                             (sg.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT) &&
                             (sg.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT);
  d.computeSubgroupBallot =
      (sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) && (sg.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT);
  switch (p.vendorID) {
    case 0x10DE: d.vendor = "NVIDIA"; break;
    case 0x1002: d.vendor = "AMD"; break;
    case 0x8086: d.vendor = "Intel"; break;
    case 0x13B5: d.vendor = "ARM"; break;
    case 0x5143: d.vendor = "Qualcomm"; break;
    case 0x10005: d.vendor = "Mesa"; break;
    default: d.vendor = "unknown";
  }
  d.driverName = drv.driverName;
  d.driverInfo = drv.driverInfo;
  if (p.vendorID == 0x10DE)  // NVIDIA packs 10.8.8.6 bits
    d.driverVersion = std::to_string(p.driverVersion >> 22) + "." + std::to_string((p.driverVersion >> 14) & 0xff) +
                      "." + std::to_string((p.driverVersion >> 6) & 0xff);
  else
    d.driverVersion = versionString(p.driverVersion);
  d.apiVersion = versionString(p.apiVersion);
  char uuid[40];
  const uint8_t* u = idProps.deviceUUID;
  std::snprintf(uuid, sizeof uuid, "%02x%02x%02x%02x-%02x%02x-%02x%02x-%02x%02x-%02x%02x%02x%02x%02x%02x", u[0], u[1],
                u[2], u[3], u[4], u[5], u[6], u[7], u[8], u[9], u[10], u[11], u[12], u[13], u[14], u[15]);
  d.uuid = uuid;
  auto exts = deviceExtensions(pd);
  d.accelerationStructure = hasExtension(exts, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
                            hasExtension(exts, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  d.rayQuery = d.accelerationStructure && hasExtension(exts, VK_KHR_RAY_QUERY_EXTENSION_NAME);
  d.rayTracingPipeline = d.accelerationStructure && hasExtension(exts, VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
  d.pipelineStatistics = hasExtension(exts, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
  uint32_t bits = 0;
  pickQueueFamily(pd, &bits);
  d.timestampValidBits = bits;
  d.timestampPeriodNs = p.limits.timestampPeriod;
  d.timestamps = bits > 0 && (p.limits.timestampComputeAndGraphics == VK_TRUE || bits > 0);
  return d;
}

// On the NVIDIA driver (580, an H200), a process that had created and destroyed about thirty
// instances could create no more: vkCreateInstance returned VK_ERROR_INCOMPATIBLE_DRIVER from then
// on (every GPU test after about the fifteenth of a process failed in its set-up:
// results/h200/gpu-tests-36). The loader unloads a driver's library with the last instance that
// uses it and loads it again with the next. One instance that enables no layer of its own (implicit
// layers still load), made before the first and never destroyed (below), keeps every driver loaded for
// the process's life. Where it cannot be made (no driver yet), the instance that follows reports
// why, and the next call tries again.
static void keepDriversLoaded() {
  // Never destroyed: at exit the driver's own destructors (registered when the loader opened it,
  // after this object was made) run first, and a vkDestroyInstance after them crashed the NVIDIA
  // driver (every command exited with SIGSEGV after writing its results). The process's end
  // releases the instance; a pointer in a static keeps it reachable for leak checkers.
  struct KeepAlive {
    std::mutex mutex;
    VkInstance inst = VK_NULL_HANDLE;
  };
  static KeepAlive* const keep = new KeepAlive;
  const std::lock_guard<std::mutex> lock(keep->mutex);
  if (keep->inst) return;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "hybridbench (keeps the drivers loaded)";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  if (vkCreateInstance(&ci, nullptr, &keep->inst) != VK_SUCCESS) keep->inst = VK_NULL_HANDLE;
}

static VkInstance createInstance(bool validation) {
  keepDriversLoaded();
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "hybridbench";
  app.apiVersion = VK_API_VERSION_1_3;
  std::vector<const char*> layers, exts;
  if (validation) {
    layers.push_back("VK_LAYER_KHRONOS_validation");
    exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    exts.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);  // the layer's own
  }
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  // Synchronization validation too: every barrier comes from declared accesses (sync.h), and a
  // declaration that misses an access (a shader's statically used binding, a step's write) is a
  // hazard only this check reports. It costs little: the full test suite ran in 460 s with it on
  // lavapipe (2 cores), as it did without.
  const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  if (validation) ci.pNext = &features;
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = uint32_t(exts.size());
  ci.ppEnabledExtensionNames = exts.data();
  VkInstance inst = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &inst);
  if (r == VK_ERROR_LAYER_NOT_PRESENT)
    throw InputError(
        "HYBRIDBENCH_VALIDATION=1 but the Khronos validation layer is not installed; install vulkan-validationlayers "
        "or unset HYBRIDBENCH_VALIDATION");
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw DeviceError(
        "no Vulkan driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); install a Vulkan driver (e.g. "
        "mesa-vulkan-drivers) or set VK_DRIVER_FILES to its ICD json");
  vkCheck(r, "vkCreateInstance");
  return inst;
}

static std::vector<VkPhysicalDevice> physicalDevices(VkInstance inst) {
  uint32_t n = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(inst, &n, nullptr));
  std::vector<VkPhysicalDevice> pds(n);
  VK_CHECK(vkEnumeratePhysicalDevices(inst, &n, pds.data()));
  return pds;
}

std::vector<DeviceInfo> enumerateDevices() {
  VkInstance inst = createInstance(false);
  std::vector<DeviceInfo> out;
  auto pds = physicalDevices(inst);
  for (uint32_t i = 0; i < pds.size(); ++i) out.push_back(describe(pds[i], i));
  vkDestroyInstance(inst, nullptr);
  return out;
}

uint32_t resolveDevice(const std::vector<DeviceInfo>& devices, const std::string& selector) {
  std::string list;
  for (const auto& d : devices) list += (list.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
  if (devices.empty()) throw DeviceError("no Vulkan device found; install a driver (lavapipe: mesa-vulkan-drivers)");
  if (selector.empty()) return 0;
  if (std::all_of(selector.begin(), selector.end(), ::isdigit)) {
    unsigned long idx = std::stoul(selector);
    if (idx >= devices.size())
      throw InputError("--device " + selector + ": no device with that index; devices are " + list);
    return uint32_t(idx);
  }
  for (const auto& d : devices)
    if (asciiLower(d.name).find(asciiLower(selector)) != std::string::npos) return d.index;
  throw InputError("--device \"" + selector + "\": no device name contains it; devices are " + list);
}

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                            VkDebugUtilsMessageTypeFlagsEXT,
                                                            const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                            void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    auto* self = static_cast<VulkanContext*>(user);
    const uint32_t n = ++self->validationMessages_;
    if (n <= 10) std::fprintf(stderr, "validation: %s\n", data->pMessage);
    if (n == 10) std::fprintf(stderr, "validation: (further messages are counted, not printed)\n");
  }
  return VK_FALSE;
}

// How long one submission may take before the device counts as hung. Generous by default: an
// analysis frame at 3840x2160 on lavapipe takes minutes; a GPU finishes any of ours in seconds.
double gpuTimeoutSeconds() {
  const char* v = std::getenv("HYBRIDBENCH_GPU_TIMEOUT_S");
  if (!v) return 300.0;
  char* end = nullptr;
  const double s = std::strtod(v, &end);
  if (end == v || *end != '\0' || !(s > 0.0))
    throw InputError(std::string("HYBRIDBENCH_GPU_TIMEOUT_S=") + v + ": expected a number of seconds > 0, e.g. 60");
  return s;
}

VulkanContext::VulkanContext(uint32_t deviceIndex) {
  timeoutSeconds_ = gpuTimeoutSeconds();  // a bad value is an InputError before any work
  validation_ = validationRequested();
  instance_ = createInstance(validation_);
  if (validation_) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = debugCallback;
    mi.pUserData = this;
    VK_CHECK(create(instance_, &mi, nullptr, &messenger_));
  }
  auto pds = physicalDevices(instance_);
  HB_ASSERT(deviceIndex < pds.size());
  physical_ = pds[deviceIndex];
  info_ = describe(physical_, deviceIndex);
  vkGetPhysicalDeviceProperties(physical_, &props_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memProps_);
  queueFamily_ = pickQueueFamily(physical_, nullptr);
  if (queueFamily_ == UINT32_MAX)
    throw DeviceError("device \"" + info_.name + "\" has no graphics+compute queue; pick another with --device");

  // Query what the device supports, then enable the subset we use.
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rtpF{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  VkPhysicalDeviceRayQueryFeaturesKHR rqF{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR asF{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR pepF{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan11Features f11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &f11;
  f11.pNext = &f12;
  f12.pNext = &f13;
  void** tail = &f13.pNext;
  if (info_.accelerationStructure) {
    *tail = &asF;
    tail = &asF.pNext;
  }
  if (info_.rayQuery) {
    *tail = &rqF;
    tail = &rqF.pNext;
  }
  if (info_.rayTracingPipeline) {
    *tail = &rtpF;
    tail = &rtpF.pNext;
  }
  if (info_.pipelineStatistics) {
    *tail = &pepF;
    tail = &pepF.pNext;
  }
  vkGetPhysicalDeviceFeatures2(physical_, &f2);
  if (info_.pipelineStatistics && !pepF.pipelineExecutableInfo) info_.pipelineStatistics = false;
  if (props_.apiVersion < VK_API_VERSION_1_3 || !f13.dynamicRendering || !f13.synchronization2)
    throw DeviceError("device \"" + info_.name +
                      "\" lacks Vulkan 1.3 dynamic rendering/synchronization2; hybridbench needs a Vulkan 1.3 device");
  if (info_.accelerationStructure && (!asF.accelerationStructure || !f12.bufferDeviceAddress)) {
    info_.accelerationStructure = info_.rayQuery = info_.rayTracingPipeline = false;
  }
  if (info_.rayQuery && !rqF.rayQuery) info_.rayQuery = false;
  if (info_.rayTracingPipeline && !rtpF.rayTracingPipeline) info_.rayTracingPipeline = false;
  info_.bufferInt64Atomics = f12.shaderBufferInt64Atomics;  // 3D rasterization's depth|id atomicMin
  info_.shaderFloat64 = f2.features.shaderFloat64;          // its fp64 fallback at shared vertices

  VkPhysicalDeviceFeatures2 en2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  VkPhysicalDeviceVulkan11Features en11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  VkPhysicalDeviceVulkan12Features en12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan13Features en13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR enAs{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  VkPhysicalDeviceRayQueryFeaturesKHR enRq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR enRtp{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  en2.pNext = &en11;
  en11.pNext = &en12;
  en12.pNext = &en13;
  en2.features.shaderInt64 = f2.features.shaderInt64;
  en2.features.shaderFloat64 = f2.features.shaderFloat64;
  en12.shaderBufferInt64Atomics = f12.shaderBufferInt64Atomics;
  en2.features.geometryShader = f2.features.geometryShader;  // gl_PrimitiveID in fragment shaders (analysis)
  en2.features.fragmentStoresAndAtomics = f2.features.fragmentStoresAndAtomics;
  en2.features.samplerAnisotropy = f2.features.samplerAnisotropy;
  en2.features.shaderStorageImageWriteWithoutFormat = f2.features.shaderStorageImageWriteWithoutFormat;
  en11.shaderDrawParameters = f11.shaderDrawParameters;
  en12.bufferDeviceAddress = f12.bufferDeviceAddress;
  en12.descriptorIndexing = f12.descriptorIndexing;
  en12.runtimeDescriptorArray = f12.runtimeDescriptorArray;
  en12.shaderSampledImageArrayNonUniformIndexing = f12.shaderSampledImageArrayNonUniformIndexing;
  en12.descriptorBindingPartiallyBound = f12.descriptorBindingPartiallyBound;
  en12.descriptorBindingVariableDescriptorCount = f12.descriptorBindingVariableDescriptorCount;
  en12.scalarBlockLayout = f12.scalarBlockLayout;
  en12.hostQueryReset = f12.hostQueryReset;
  en12.shaderInt8 = f12.shaderInt8;
  en12.storageBuffer8BitAccess = f12.storageBuffer8BitAccess;
  en13.dynamicRendering = VK_TRUE;
  en13.synchronization2 = VK_TRUE;
  en13.maintenance4 = f13.maintenance4;
  std::vector<const char*> exts;
  void** enTail = &en13.pNext;
  if (info_.accelerationStructure) {
    exts.push_back(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME);
    exts.push_back(VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
    enAs.accelerationStructure = VK_TRUE;
    *enTail = &enAs;
    enTail = &enAs.pNext;
  }
  if (info_.rayQuery) {
    exts.push_back(VK_KHR_RAY_QUERY_EXTENSION_NAME);
    enRq.rayQuery = VK_TRUE;
    *enTail = &enRq;
    enTail = &enRq.pNext;
  }
  if (info_.rayTracingPipeline) {
    exts.push_back(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
    enRtp.rayTracingPipeline = VK_TRUE;
    *enTail = &enRtp;
    enTail = &enRtp.pNext;
  }
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR enPep{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  if (info_.pipelineStatistics) {
    exts.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
    enPep.pipelineExecutableInfo = VK_TRUE;
    *enTail = &enPep;
    enTail = &enPep.pNext;
  }
  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = queueFamily_;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &en2;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.enabledExtensionCount = uint32_t(exts.size());
  dci.ppEnabledExtensionNames = exts.data();
  VK_CHECK(vkCreateDevice(physical_, &dci, nullptr, &device_));
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  if (info_.pipelineStatistics) {
    getExecutableProperties = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
        vkGetDeviceProcAddr(device_, "vkGetPipelineExecutablePropertiesKHR"));
    getExecutableStatistics = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
        vkGetDeviceProcAddr(device_, "vkGetPipelineExecutableStatisticsKHR"));
    if (!getExecutableProperties || !getExecutableStatistics) info_.pipelineStatistics = false;
  }

  if (info_.accelerationStructure) {
#define HB_LOAD(member, name) rt_.member = reinterpret_cast<PFN_##name>(vkGetDeviceProcAddr(device_, #name))
    HB_LOAD(createAccelerationStructure, vkCreateAccelerationStructureKHR);
    HB_LOAD(destroyAccelerationStructure, vkDestroyAccelerationStructureKHR);
    HB_LOAD(getBuildSizes, vkGetAccelerationStructureBuildSizesKHR);
    HB_LOAD(cmdBuild, vkCmdBuildAccelerationStructuresKHR);
    HB_LOAD(getAddress, vkGetAccelerationStructureDeviceAddressKHR);
    if (info_.rayTracingPipeline) {
      HB_LOAD(createRayTracingPipelines, vkCreateRayTracingPipelinesKHR);
      HB_LOAD(getShaderGroupHandles, vkGetRayTracingShaderGroupHandlesKHR);
      HB_LOAD(cmdTraceRays, vkCmdTraceRaysKHR);
      rtProps_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR;
      VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &rtProps_};
      vkGetPhysicalDeviceProperties2(physical_, &p2);
    }
#undef HB_LOAD
  }

  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pci.queueFamilyIndex = queueFamily_;
  VK_CHECK(vkCreateCommandPool(device_, &pci, nullptr, &pool_));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_CHECK(vkCreateFence(device_, &fci, nullptr, &fence_));
}

VulkanContext::~VulkanContext() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

void VulkanContext::submitAndWait(const std::function<void(VkCommandBuffer)>& fn, const char* what) const {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VK_CHECK(vkAllocateCommandBuffers(device_, &ai, &cmd));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
  fn(cmd);
  VK_CHECK(vkEndCommandBuffer(cmd));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  VK_CHECK(vkResetFences(device_, 1, &fence_));
  VK_CHECK(vkQueueSubmit(queue_, 1, &si, fence_));
  const double limit = timeoutSeconds_;
  const VkResult r = vkWaitForFences(device_, 1, &fence_, VK_TRUE, uint64_t(limit * 1e9));
  if (r == VK_TIMEOUT) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "hybridbench: the GPU did not finish %s within %g s on %s; the device may be hung, so the run "
                 "stops here (files already written stay; a sweep continues with --resume; raise "
                 "HYBRIDBENCH_GPU_TIMEOUT_S if the device is merely slow)\n",
                 what, limit, info_.name.c_str());
    std::fflush(stderr);
    std::_Exit(kExitDeviceFailure);
  }
  VK_CHECK(r);
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
}

uint32_t VulkanContext::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags flags) const {
  for (uint32_t i = 0; i < memProps_.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (memProps_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  throw DeviceError("no memory type with flags " + std::to_string(flags) + " on " + info_.name);
}

}  // namespace hb
