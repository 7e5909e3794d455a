#include "gpu/device.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace aeroflock::gpu {
namespace {

const char* const validation_layer = "VK_LAYER_KHRONOS_validation";

bool validation_from_env() {
  const char* v = std::getenv("AEROFLOCK_VALIDATION");
  return v && *v && std::strcmp(v, "0") != 0;
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

bool has_instance_extension(const char* layer, const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateInstanceExtensionProperties(layer, &n, exts.data());
  for (const auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

// An instance for Vulkan 1.2; with `messenger` (validation on) it enables the Khronos layer with
// synchronization validation and reports through `messenger` from vkCreateInstance on.
VkInstance create_instance(const VkDebugUtilsMessengerCreateInfoEXT* messenger,
                           const std::vector<const char*>& wanted) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "aeroflock";
  app.pEngineName = "aeroflock";
  app.apiVersion = VK_API_VERSION_1_2;

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  std::vector<const char*> extensions = wanted;
  const VkValidationFeatureEnableEXT sync_validation =
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  if (messenger) {
    if (!has_layer(validation_layer))
      throw Error(
          "Vulkan validation was asked for (AEROFLOCK_VALIDATION=1 or --validation) "
          "but VK_LAYER_KHRONOS_validation is not installed "
          "(Debian: apt-get install vulkan-validationlayers)");
    if (!has_instance_extension(nullptr, VK_EXT_DEBUG_UTILS_EXTENSION_NAME))
      throw Error("Vulkan validation needs VK_EXT_debug_utils, which the loader lacks");
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &validation_layer;
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    info.pNext = messenger;
    if (has_instance_extension(validation_layer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME)) {
      extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
      features.enabledValidationFeatureCount = 1;
      features.pEnabledValidationFeatures = &sync_validation;
      features.pNext = messenger;
      info.pNext = &features;
    }
  }
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();

  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw Error(
        "no Vulkan driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER); "
        "install one, e.g. Debian's mesa-vulkan-drivers for the lavapipe CPU device");
  check(r, "vkCreateInstance");
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(n);
  check(vkEnumeratePhysicalDevices(instance, &n, devices.data()), "vkEnumeratePhysicalDevices");
  devices.resize(n);
  return devices;
}

DeviceInfo query(VkPhysicalDevice physical, uint32_t index) {
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(physical, &props);
  DeviceInfo info;
  info.index = index;
  info.name = props.deviceName;
  info.type = props.deviceType;
  info.api_version = props.apiVersion;
  info.max_storage_buffer_range = props.limits.maxStorageBufferRange;

  // Driver, subgroup and allocation limits (Vulkan 1.1 / 1.2 structures).
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties subgroup{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceMaintenance3Properties m3{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  subgroup.pNext = &m3;
  props2.pNext = &subgroup;
  if (props.apiVersion >= VK_API_VERSION_1_2) {
    driver.pNext = props2.pNext;
    props2.pNext = &driver;
  }
  if (props.apiVersion >= VK_API_VERSION_1_1) {
    vkGetPhysicalDeviceProperties2(physical, &props2);
    info.subgroup_size = subgroup.subgroupSize;
    info.max_allocation_size = m3.maxMemoryAllocationSize;
  }
  info.driver_name = props.apiVersion >= VK_API_VERSION_1_2 ? driver.driverName : "unknown driver";
  info.driver_info = props.apiVersion >= VK_API_VERSION_1_2 ? driver.driverInfo : "";

  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory);
  for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
    if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.device_local_heap = std::max(info.device_local_heap, memory.memoryHeaps[i].size);
  return info;
}

std::string device_list(const std::vector<DeviceInfo>& infos) {
  std::string s;
  for (const auto& info : infos) s += "\n  " + describe(info);
  return s.empty() ? "\n  (none)" : s;
}

}  // namespace

int preference(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

const char* type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

std::string version_string(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
         "." + std::to_string(VK_API_VERSION_PATCH(v));
}

std::string describe(const DeviceInfo& info) {
  return std::to_string(info.index) + ": " + info.name + " [" + type_name(info.type) + "; " +
         info.driver_name + " " + info.driver_info + "; Vulkan " +
         version_string(info.api_version) + "]";
}

std::vector<DeviceInfo> Device::list_devices() {
  VkInstance instance = create_instance(nullptr, {});
  std::vector<DeviceInfo> infos;
  try {
    auto devices = physical_devices(instance);
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(query(devices[i], i));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return infos;
}

Device::Device(const DeviceOptions& options) {
  VkDebugUtilsMessengerCreateInfoEXT messenger{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &Device::on_message;
  messenger.pUserData = this;
  const bool validation = options.validation || validation_from_env();

  instance_ = create_instance(validation ? &messenger : nullptr, options.instance_extensions);
  try {
    if (validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw Error("vkCreateDebugUtilsMessengerEXT not found");
      check(create(instance_, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
    }

    // Pick the physical device.
    auto devices = physical_devices(instance_);
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(query(devices[i], i));
    if (devices.empty())
      throw Error(
          "no Vulkan device found (the loader and a driver are there, but the driver "
          "reports no device)");
    int chosen = -1;
    if (options.index >= 0) {
      if (options.index >= static_cast<int>(devices.size()))
        throw Error("Vulkan device index " + std::to_string(options.index) +
                    " is out of range; the devices are:" + device_list(infos));
      chosen = options.index;
      if (infos[chosen].api_version < VK_API_VERSION_1_2)
        throw Error("Vulkan device " + describe(infos[chosen]) + " supports only Vulkan " +
                    version_string(infos[chosen].api_version) + "; aeroflock needs 1.2");
    } else {
      for (const auto& info : infos)
        if (info.api_version >= VK_API_VERSION_1_2 &&
            (chosen < 0 || preference(info.type) < preference(infos[chosen].type)))
          chosen = static_cast<int>(info.index);
      if (chosen < 0)
        throw Error("no Vulkan 1.2 device found; the devices are:" + device_list(infos));
    }
    physical_ = devices[chosen];
    info_ = infos[chosen];
    vkGetPhysicalDeviceProperties(physical_, &properties_);
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

    // One queue from the first family that can compute (and draw, and present, when asked).
    if (options.surface) surface_ = options.surface(instance_);
    VkQueueFlags needed = VK_QUEUE_COMPUTE_BIT;
    if (options.graphics || surface_) needed |= VK_QUEUE_GRAPHICS_BIT;
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, families.data());
    queue_family_ = UINT32_MAX;
    for (uint32_t i = 0; i < n && queue_family_ == UINT32_MAX; ++i) {
      VkBool32 present = VK_TRUE;
      if (surface_) vkGetPhysicalDeviceSurfaceSupportKHR(physical_, i, surface_, &present);
      if ((families[i].queueFlags & needed) == needed && present) queue_family_ = i;
    }
    if (queue_family_ == UINT32_MAX)
      throw Error("Vulkan device " + info_.name + " has no queue that can " +
                  (surface_                         ? "compute, draw and present"
                   : needed & VK_QUEUE_GRAPHICS_BIT ? "compute and draw"
                                                    : "compute"));
    const char* swapchain = VK_KHR_SWAPCHAIN_EXTENSION_NAME;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = queue_family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkDeviceCreateInfo create{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    create.queueCreateInfoCount = 1;
    create.pQueueCreateInfos = &queue;
    if (surface_) {
      create.enabledExtensionCount = 1;
      create.ppEnabledExtensionNames = &swapchain;
    }
    check(vkCreateDevice(physical_, &create, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  } catch (...) {
    destroy();
    throw;
  }
}

Device::~Device() { destroy(); }

void Device::destroy() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (surface_) {
    vkDestroySurfaceKHR(instance_, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

VkCommandPool Device::create_command_pool() const {
  VkCommandPoolCreateInfo info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  info.queueFamilyIndex = queue_family_;
  VkCommandPool pool = VK_NULL_HANDLE;
  check(vkCreateCommandPool(device_, &info, nullptr, &pool), "vkCreateCommandPool");
  return pool;
}

VkCommandBuffer Device::allocate_command_buffer(VkCommandPool pool) const {
  VkCommandBufferAllocateInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  info.commandPool = pool;
  info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  info.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &info, &cmd), "vkAllocateCommandBuffers");
  return cmd;
}

VkFence Device::create_fence(bool signaled) const {
  VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  if (signaled) info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VkFence fence = VK_NULL_HANDLE;
  check(vkCreateFence(device_, &info, nullptr, &fence), "vkCreateFence");
  return fence;
}

uint32_t Device::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                             VkMemoryPropertyFlags preferred) const {
  uint32_t fallback = UINT32_MAX;
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags flags = memory_.memoryTypes[i].propertyFlags;
    if (!(type_bits & (1u << i)) || (flags & required) != required) continue;
    if ((flags & preferred) == preferred) return i;
    if (fallback == UINT32_MAX) fallback = i;
  }
  return fallback;
}

VKAPI_ATTR VkBool32 VKAPI_CALL Device::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                  void* self) {
  auto* device = static_cast<Device*>(self);
  const bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  (error ? device->errors_ : device->warnings_).fetch_add(1);
  std::fprintf(stderr, "vulkan validation %s: %s\n", error ? "error" : "warning",
               data && data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

}  // namespace aeroflock::gpu
