// A colour image to render into without a window, and its pixels read back.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device.h"

namespace aeroflock::render {

class Offscreen {
 public:
  static constexpr VkFormat kFormat = VK_FORMAT_R8G8B8A8_UNORM;

  Offscreen(const gpu::Device& device, VkExtent2D extent);
  ~Offscreen();
  Offscreen(const Offscreen&) = delete;
  Offscreen& operator=(const Offscreen&) = delete;

  VkImage image() const { return image_; }
  VkImageView view() const { return view_; }
  VkExtent2D extent() const { return extent_; }
  // Copies the image (in TRANSFER_SRC_OPTIMAL, as the renderer leaves it when asked) to host
  // memory; pixels() holds it once the command buffer's fence has signalled.
  void record_copy(VkCommandBuffer cmd) const;
  // Width x height RGBA, top row first.
  std::vector<uint8_t> pixels() const;

 private:
  const gpu::Device& device_;
  VkExtent2D extent_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  gpu::Buffer readback_;
};

}  // namespace aeroflock::render
