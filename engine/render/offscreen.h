// A colour image to render into without a window, and its pixels read back.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device.h"
#include "gpu/image.h"

namespace aeroflock::render {

class Offscreen {
 public:
  static constexpr VkFormat kFormat = VK_FORMAT_R8G8B8A8_UNORM;

  Offscreen(const gpu::Device& device, VkExtent2D extent);
  Offscreen(const Offscreen&) = delete;
  Offscreen& operator=(const Offscreen&) = delete;

  VkImage image() const { return image_.handle(); }
  VkImageView view() const { return image_.view(); }
  VkExtent2D extent() const { return extent_; }
  // Copies the image (in TRANSFER_SRC_OPTIMAL, as the renderer leaves it when asked) to host
  // memory; pixels() holds it once the command buffer's fence has signalled.
  void record_copy(VkCommandBuffer cmd) const;
  // Width x height RGBA, top row first.
  std::vector<uint8_t> pixels() const;

 private:
  VkExtent2D extent_;
  gpu::Image image_;
  gpu::Buffer readback_;
};

}  // namespace aeroflock::render
