#pragma once
// Storage buffers: device-local for the simulation state, host-visible (mapped) for upload and
// readback.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "gpu/device.h"

namespace aeroflock::gpu {

enum class Memory {
  device_local,  // fastest for the shaders; mapped too where the device allows (lavapipe, UMA)
  host,          // host-visible, coherent, cached where possible, always mapped
};

// A storage buffer that can also be copied from and to, hold indirect draw arguments and be read as
// texels (compute.h: Binding). Destroy it only when the device no longer
// uses it (a Submitter's destructor waits for its frames).
class Buffer {
 public:
  Buffer(const Device& device, VkDeviceSize size, Memory memory);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  bool host_visible() const { return mapped_ != nullptr; }
  // The mapped memory (host-coherent), or nullptr when the buffer is not host-visible.
  std::byte* mapped() const { return mapped_; }

  // Copies `data` to `offset`: straight into the mapped memory, or through a staging buffer
  // and a copy on the queue (waited for). The device must not be using the buffer.
  void upload(std::span<const std::byte> data, VkDeviceSize offset = 0);
  // The whole buffer, after all work submitted so far (waits for the queue's earlier writes
  // through a barrier and a fence; for setup and tests, not for every frame).
  std::vector<std::byte> download() const;

 private:
  void destroy();

  const Device* device_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  std::byte* mapped_ = nullptr;
};

// Throws Error unless `bytes` (that many bytes of `element_size` each, e.g. the birds' state) fit
// in one storage buffer of the device: maxStorageBufferRange, maxMemoryAllocationSize and the
// largest device-local heap. The message names the limit and the most elements that fit, e.g.
// "2000000 birds need 352000000 bytes in one storage buffer; llvmpipe (...) allows 134217728
// (maxStorageBufferRange): at most 762600 birds".
void check_storage_size(const Device& device, VkDeviceSize bytes, size_t element_size,
                        std::string_view what = "birds");
// The most elements of `element_size` bytes that one storage buffer of the device holds, by the
// same limits.
VkDeviceSize storage_capacity(const Device& device, size_t element_size);

}  // namespace aeroflock::gpu
