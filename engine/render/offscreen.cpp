#include "render/offscreen.h"

#include <cstring>

#include "gpu/compute.h"

namespace aeroflock::render {

Offscreen::Offscreen(const gpu::Device& device, VkExtent2D extent)
    : extent_(extent),
      image_(device, extent, kFormat,
             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
             VK_IMAGE_ASPECT_COLOR_BIT),
      readback_(device, VkDeviceSize(extent.width) * extent.height * 4, gpu::Memory::host) {}

void Offscreen::record_copy(VkCommandBuffer cmd) const {
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent_.width, extent_.height, 1};
  vkCmdCopyImageToBuffer(cmd, image_.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                         readback_.handle(), 1, &region);
  gpu::barrier_to_host(cmd);
}

std::vector<uint8_t> Offscreen::pixels() const {
  std::vector<uint8_t> out(size_t(extent_.width) * extent_.height * 4);
  std::memcpy(out.data(), readback_.mapped(), out.size());
  return out;
}

}  // namespace aeroflock::render
