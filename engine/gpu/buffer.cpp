#include "gpu/buffer.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "gpu/compute.h"

namespace aeroflock::gpu {

Buffer::Buffer(const Device& device, VkDeviceSize size, Memory memory)
    : device_(&device), size_(size) {
  if (size == 0) throw Error("a Vulkan buffer of 0 bytes");
  VkDevice dev = device.handle();
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
               VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(dev, &info, nullptr, &buffer_), "vkCreateBuffer");

  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(dev, buffer_, &req);
    const VkMemoryPropertyFlags host =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    uint32_t type =
        memory == Memory::host
            ? device.memory_type(req.memoryTypeBits, host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT)
            : device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX && memory == Memory::device_local)
      type = device.memory_type(req.memoryTypeBits, 0);
    if (type == UINT32_MAX)
      throw Error("Vulkan device " + device.name() + " has no " +
                  (memory == Memory::host ? "host-visible coherent" : "") +
                  " memory type for a storage buffer");

    // Larger allocations are invalid usage (lavapipe even grants them): a clear error instead.
    const VkDeviceSize heap =
        device.memory().memoryHeaps[device.memory().memoryTypes[type].heapIndex].size;
    const VkDeviceSize max_alloc = device.info().max_allocation_size;
    if (req.size > heap || (max_alloc > 0 && req.size > max_alloc)) {
      const bool by_heap = req.size > heap && (max_alloc == 0 || heap <= max_alloc);
      throw Error("a buffer of " + std::to_string(size) + " bytes; " + device.name() + " allows " +
                  std::to_string(by_heap ? heap : max_alloc) +
                  (by_heap ? " (its memory heap)" : " (maxMemoryAllocationSize)"));
    }
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = type;
    VkResult r = vkAllocateMemory(dev, &alloc, nullptr, &memory_);
    if (r != VK_SUCCESS)
      throw Error("allocating " + std::to_string(req.size) + " bytes on " + device.name() + ": " +
                  to_string(r));
    check(vkBindBufferMemory(dev, buffer_, memory_, 0), "vkBindBufferMemory");

    const VkMemoryPropertyFlags flags = device.memory().memoryTypes[type].propertyFlags;
    if ((flags & host) == host) {
      void* p = nullptr;
      check(vkMapMemory(dev, memory_, 0, VK_WHOLE_SIZE, 0, &p), "vkMapMemory");
      mapped_ = static_cast<std::byte*>(p);
    }
  } catch (...) {
    destroy();
    throw;
  }
}

Buffer::~Buffer() { destroy(); }

void Buffer::destroy() {
  if (!device_) return;
  if (memory_) vkFreeMemory(device_->handle(), memory_, nullptr);  // unmaps too
  if (buffer_) vkDestroyBuffer(device_->handle(), buffer_, nullptr);
  memory_ = VK_NULL_HANDLE;
  buffer_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
}

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    destroy();
    device_ = std::exchange(other.device_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

void Buffer::upload(std::span<const std::byte> data, VkDeviceSize offset) {
  if (offset > size_ || data.size() > size_ - offset)
    throw Error("upload of " + std::to_string(data.size()) + " bytes at " + std::to_string(offset) +
                " into a buffer of " + std::to_string(size_));
  if (data.empty()) return;
  if (mapped_) {  // host-coherent: visible to the device at the next queue submission
    std::memcpy(mapped_ + offset, data.data(), data.size());
    return;
  }
  Buffer staging(*device_, data.size(), Memory::host);
  std::memcpy(staging.mapped(), data.data(), data.size());
  Submitter(*device_).run([&](VkCommandBuffer cmd) {
    barrier_to_transfer(cmd);  // earlier work on this buffer before the copy overwrites it
    copy_buffer(cmd, staging, *this, data.size(), 0, offset);
    barrier_to_compute(cmd);
  });
}

std::vector<std::byte> Buffer::download() const {
  std::vector<std::byte> out(size_);
  if (mapped_) {
    Submitter(*device_).run([](VkCommandBuffer cmd) { barrier_to_host(cmd); });
    std::memcpy(out.data(), mapped_, size_);
    return out;
  }
  Buffer staging(*device_, size_, Memory::host);
  Submitter(*device_).run([&](VkCommandBuffer cmd) { record_readback(cmd, *this, staging); });
  std::memcpy(out.data(), staging.mapped(), size_);
  return out;
}

VkDeviceSize storage_capacity(const Device& device, size_t element_size) {
  if (element_size == 0) throw std::invalid_argument("storage_capacity: element_size 0");
  const DeviceInfo& info = device.info();
  VkDeviceSize most = ~VkDeviceSize{0};
  for (VkDeviceSize limit :
       {info.max_storage_buffer_range, info.max_allocation_size, info.device_local_heap})
    if (limit > 0) most = std::min(most, limit);
  return most / element_size;
}

void check_storage_size(const Device& device, VkDeviceSize bytes, size_t element_size,
                        std::string_view what) {
  if (element_size == 0) throw std::invalid_argument("check_storage_size: element_size 0");
  const DeviceInfo& info = device.info();
  struct Limit {
    VkDeviceSize bytes;
    const char* name;
  };
  const Limit limits[] = {
      {info.max_storage_buffer_range, "maxStorageBufferRange"},
      {info.max_allocation_size, "maxMemoryAllocationSize"},
      {info.device_local_heap, "the largest device-local memory heap"},
  };
  const Limit* tightest = nullptr;
  for (const Limit& l : limits)
    if (l.bytes > 0 && bytes > l.bytes && (!tightest || l.bytes < tightest->bytes)) tightest = &l;
  if (!tightest) return;
  const VkDeviceSize count = (bytes + element_size - 1) / element_size;
  throw Error(std::to_string(count) + " " + std::string(what) + " need " + std::to_string(bytes) +
              " bytes in one storage buffer; " + device.name() + " allows " +
              std::to_string(tightest->bytes) + " (" + tightest->name + "): at most " +
              std::to_string(tightest->bytes / element_size) + " " + std::string(what));
}

}  // namespace aeroflock::gpu
