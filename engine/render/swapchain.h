// The window's swapchain: its images and views, a semaphore per image that its rendering signals
// for the presentation, and re-creation when the window changes size.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "gpu/device.h"

namespace aeroflock::render {

class Swapchain {
 public:
  // FIFO presentation (vsync; always available), B8G8R8A8_UNORM where the surface has it.
  Swapchain(const gpu::Device& device, VkExtent2D wanted);
  ~Swapchain();  // waits for the device to be idle
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // A new swapchain of (about) `wanted` size, after the device has gone idle; the images,
  // views and semaphores change.
  void recreate(VkExtent2D wanted);

  // The next image, signalling `acquired` when it is ready. False when the swapchain is out of
  // date (recreate it); a suboptimal image is still returned and needs_recreate() becomes true.
  bool acquire(VkSemaphore acquired, uint32_t& image);
  // Presents `image` once `render_finished(image)` is signalled. False when the swapchain is
  // out of date or suboptimal (recreate it).
  bool present(uint32_t image);

  bool needs_recreate() const { return suboptimal_; }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  uint32_t image_count() const { return static_cast<uint32_t>(images_.size()); }
  VkImage image(uint32_t i) const { return images_[i]; }
  VkImageView view(uint32_t i) const { return views_[i]; }
  VkSemaphore render_finished(uint32_t i) const { return render_finished_[i]; }

 private:
  void create(VkExtent2D wanted, VkSwapchainKHR old);
  void destroy_images();

  const gpu::Device& device_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{};
  std::vector<VkImage> images_;
  std::vector<VkImageView> views_;
  std::vector<VkSemaphore> render_finished_;
  bool suboptimal_ = false;
};

}  // namespace aeroflock::render
