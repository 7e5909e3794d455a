#pragma once
// The Vulkan instance, the physical device and a logical device with one compute queue.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gpu/error.h"

namespace aeroflock::gpu {

// One physical device, as list_devices() sees it.
struct DeviceInfo {
  uint32_t index = 0;  // position in vkEnumeratePhysicalDevices
  std::string name;    // "llvmpipe (LLVM 15.0.6, 256 bits)"
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  std::string driver_name;                    // "llvmpipe" (VkPhysicalDeviceDriverProperties)
  std::string driver_info;                    // "Mesa 22.3.6 (LLVM 15.0.6)"
  uint32_t api_version = 0;                   // VK_MAKE_API_VERSION
  VkDeviceSize max_storage_buffer_range = 0;  // bytes one storage-buffer binding may cover
  VkDeviceSize max_allocation_size = 0;       // maxMemoryAllocationSize (Maintenance3)
  VkDeviceSize device_local_heap = 0;         // size of the largest device-local heap
  uint32_t subgroup_size = 0;
};

// Which kind of device is preferred, lower first: discrete, integrated, virtual, cpu, other.
int preference(VkPhysicalDeviceType type);
// "cpu", "discrete GPU", "integrated GPU", "virtual GPU", "other".
const char* type_name(VkPhysicalDeviceType type);
// "1.3.230".
std::string version_string(uint32_t api_version);
// "0: llvmpipe (LLVM 15.0.6, 256 bits) [cpu; llvmpipe Mesa 22.3.6 (LLVM 15.0.6); Vulkan 1.3.230]"
std::string describe(const DeviceInfo& info);

struct DeviceOptions {
  int index = -1;           // >= 0: that device; < 0: a discrete GPU, else integrated, virtual, cpu
  bool validation = false;  // Khronos validation layer; AEROFLOCK_VALIDATION=1 also turns it on
  bool graphics = false;    // the queue must also do graphics (rendering)
  // For a window: the instance extensions the windowing system needs, and a function that makes
  // the window's surface once the instance exists. The device then owns the surface, its queue
  // can present to it, and VK_KHR_swapchain is enabled.
  std::vector<const char*> instance_extensions;
  std::function<VkSurfaceKHR(VkInstance)> surface;
};

// Options for a headless device: that device index (< 0: the preferred one), validation on or off.
inline DeviceOptions headless(int index, bool validation) {
  DeviceOptions o;
  o.index = index;
  o.validation = validation;
  return o;
}

class Device {
 public:
  explicit Device(const DeviceOptions& options = {});
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // Every Vulkan device of the machine (an empty list when there is a loader but no device).
  // Error when there is no Vulkan loader or driver at all.
  static std::vector<DeviceInfo> list_devices();

  const DeviceInfo& info() const { return info_; }
  const std::string& name() const { return info_.name; }
  std::string driver() const { return info_.driver_name + " " + info_.driver_info; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }
  const VkPhysicalDeviceMemoryProperties& memory() const { return memory_; }

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice handle() const { return device_; }
  VkQueue queue() const { return queue_; }
  VkSurfaceKHR surface() const { return surface_; }  // VK_NULL_HANDLE without a window
  uint32_t queue_family() const { return queue_family_; }

  // The first memory type allowed by `type_bits` that has all of `required` (and, among those,
  // all of `preferred` if one has); UINT32_MAX if none.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                       VkMemoryPropertyFlags preferred = 0) const;

  // Command pools, command buffers and fences on this device's queue (the caller destroys them;
  // destroying the pool frees its command buffers). Error on failure.
  VkCommandPool create_command_pool() const;
  VkCommandBuffer allocate_command_buffer(VkCommandPool pool) const;
  VkFence create_fence(bool signaled = false) const;

  bool validation() const { return messenger_ != VK_NULL_HANDLE; }
  // Messages of the validation layer so far (each is also printed to stderr).
  int validation_errors() const { return errors_.load(); }
  int validation_warnings() const { return warnings_.load(); }

 private:
  void destroy();
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT types,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* self);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  DeviceInfo info_;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  std::atomic<int> errors_{0};
  std::atomic<int> warnings_{0};
};

}  // namespace aeroflock::gpu
