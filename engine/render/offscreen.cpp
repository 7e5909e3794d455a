#include "render/offscreen.h"

#include <cstring>

#include "gpu/compute.h"
#include "gpu/error.h"

namespace aeroflock::render {

using gpu::check;

Offscreen::Offscreen(const gpu::Device& device, VkExtent2D extent)
    : device_(device),
      extent_(extent),
      readback_(device, VkDeviceSize(extent.width) * extent.height * 4, gpu::Memory::host) {
  VkDevice dev = device.handle();
  VkImageCreateInfo image{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  image.imageType = VK_IMAGE_TYPE_2D;
  image.format = kFormat;
  image.extent = {extent.width, extent.height, 1};
  image.mipLevels = 1;
  image.arrayLayers = 1;
  image.samples = VK_SAMPLE_COUNT_1_BIT;
  image.tiling = VK_IMAGE_TILING_OPTIMAL;
  image.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  check(vkCreateImage(dev, &image, nullptr, &image_), "vkCreateImage (offscreen)");
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(dev, image_, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (alloc.memoryTypeIndex == UINT32_MAX) alloc.memoryTypeIndex = device.memory_type(req.memoryTypeBits, 0);
  check(vkAllocateMemory(dev, &alloc, nullptr, &memory_), "vkAllocateMemory (offscreen)");
  check(vkBindImageMemory(dev, image_, memory_, 0), "vkBindImageMemory (offscreen)");
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = image_;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = kFormat;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  check(vkCreateImageView(dev, &view, nullptr, &view_), "vkCreateImageView (offscreen)");
}

Offscreen::~Offscreen() {
  VkDevice dev = device_.handle();
  vkDeviceWaitIdle(dev);
  vkDestroyImageView(dev, view_, nullptr);
  vkDestroyImage(dev, image_, nullptr);
  vkFreeMemory(dev, memory_, nullptr);
}

void Offscreen::record_copy(VkCommandBuffer cmd) const {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent_.width, extent_.height, 1};
  vkCmdCopyImageToBuffer(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.handle(), 1,
                         &region);
  gpu::barrier_to_host(cmd);
}

std::vector<uint8_t> Offscreen::pixels() const {
  std::vector<uint8_t> out(size_t(extent_.width) * extent_.height * 4);
  std::memcpy(out.data(), readback_.mapped(), out.size());
  return out;
}

}  // namespace aeroflock::render
