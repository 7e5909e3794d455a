#pragma once
// A 2D image with its own memory and a view of it (depth buffers, offscreen colour targets).
#include <vulkan/vulkan.h>

#include "gpu/device.h"

namespace aeroflock::gpu {

class Image {
 public:
  // Device-local where the device has such memory; `aspect`: colour or depth; `samples` > 1 for
  // a multisampled attachment.
  Image(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
        VkImageAspectFlags aspect, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);
  ~Image();
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }

 private:
  void destroy();
  const Device& device_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
};

}  // namespace aeroflock::gpu
