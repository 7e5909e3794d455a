#include "render/swapchain.h"

#include <algorithm>

#include "gpu/error.h"

namespace aeroflock::render {
namespace {

using gpu::check;

VkSurfaceFormatKHR choose_format(const gpu::Device& device) {
  uint32_t n = 0;
  check(vkGetPhysicalDeviceSurfaceFormatsKHR(device.physical(), device.surface(), &n, nullptr),
        "vkGetPhysicalDeviceSurfaceFormatsKHR");
  std::vector<VkSurfaceFormatKHR> formats(n);
  check(
      vkGetPhysicalDeviceSurfaceFormatsKHR(device.physical(), device.surface(), &n, formats.data()),
      "vkGetPhysicalDeviceSurfaceFormatsKHR");
  if (formats.empty()) throw gpu::Error("the window's surface offers no image format");
  // UNORM first: the render shaders write display colours, as into the PNGs' R8G8B8A8_UNORM.
  for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM,
                          VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB})
    for (const VkSurfaceFormatKHR& f : formats)
      if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
  return formats[0];
}

VkExtent2D choose_extent(const VkSurfaceCapabilitiesKHR& caps, VkExtent2D wanted) {
  if (caps.currentExtent.width != UINT32_MAX) return caps.currentExtent;
  return {std::clamp(wanted.width, caps.minImageExtent.width, caps.maxImageExtent.width),
          std::clamp(wanted.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
}

VkCompositeAlphaFlagBitsKHR choose_alpha(VkCompositeAlphaFlagsKHR supported) {
  for (VkCompositeAlphaFlagBitsKHR a :
       {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
        VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR, VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
    if (supported & a) return a;
  return VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
}

}  // namespace

Swapchain::Swapchain(const gpu::Device& device, VkExtent2D wanted) : device_(device) {
  try {
    create(wanted, VK_NULL_HANDLE);
  } catch (...) {
    destroy_images();
    if (swapchain_) vkDestroySwapchainKHR(device_.handle(), swapchain_, nullptr);
    throw;
  }
}

Swapchain::~Swapchain() {
  vkDeviceWaitIdle(device_.handle());
  destroy_images();
  if (swapchain_) vkDestroySwapchainKHR(device_.handle(), swapchain_, nullptr);
}

void Swapchain::recreate(VkExtent2D wanted) {
  check(vkDeviceWaitIdle(device_.handle()), "vkDeviceWaitIdle");
  destroy_images();
  VkSwapchainKHR old = swapchain_;
  swapchain_ = VK_NULL_HANDLE;
  try {
    create(wanted, old);
  } catch (...) {
    vkDestroySwapchainKHR(device_.handle(), old, nullptr);
    throw;
  }
  vkDestroySwapchainKHR(device_.handle(), old, nullptr);
}

void Swapchain::create(VkExtent2D wanted, VkSwapchainKHR old) {
  VkDevice dev = device_.handle();
  VkSurfaceCapabilitiesKHR caps;
  check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_.physical(), device_.surface(), &caps),
        "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  const VkSurfaceFormatKHR format = choose_format(device_);
  format_ = format.format;
  extent_ = choose_extent(caps, wanted);
  suboptimal_ = false;

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = device_.surface();
  info.minImageCount = caps.minImageCount + 1;
  if (caps.maxImageCount > 0) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent_;
  info.imageArrayLayers = 1;
  // Transfer too, where allowed, for renderers that clear or copy into the image.
  info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                    (caps.supportedUsageFlags &
                     (VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT));
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = choose_alpha(caps.supportedCompositeAlpha);
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
  info.clipped = VK_TRUE;
  info.oldSwapchain = old;
  check(vkCreateSwapchainKHR(dev, &info, nullptr, &swapchain_), "vkCreateSwapchainKHR");

  uint32_t n = 0;
  check(vkGetSwapchainImagesKHR(dev, swapchain_, &n, nullptr), "vkGetSwapchainImagesKHR");
  images_.resize(n);
  check(vkGetSwapchainImagesKHR(dev, swapchain_, &n, images_.data()), "vkGetSwapchainImagesKHR");
  for (VkImage image : images_) {
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format_;
    view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    check(vkCreateImageView(dev, &view, nullptr, &views_.emplace_back()), "vkCreateImageView");
    VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    check(vkCreateSemaphore(dev, &semaphore, nullptr, &render_finished_.emplace_back()),
          "vkCreateSemaphore");
  }
}

void Swapchain::destroy_images() {
  VkDevice dev = device_.handle();
  for (VkImageView v : views_)
    if (v) vkDestroyImageView(dev, v, nullptr);
  for (VkSemaphore s : render_finished_)
    if (s) vkDestroySemaphore(dev, s, nullptr);
  views_.clear();
  render_finished_.clear();
  images_.clear();
}

bool Swapchain::acquire(VkSemaphore acquired, uint32_t& image) {
  const VkResult r = vkAcquireNextImageKHR(device_.handle(), swapchain_, UINT64_MAX, acquired,
                                           VK_NULL_HANDLE, &image);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) return false;
  if (r == VK_SUBOPTIMAL_KHR) {
    suboptimal_ = true;
    return true;
  }
  check(r, "vkAcquireNextImageKHR");
  return true;
}

bool Swapchain::present(uint32_t image) {
  VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  info.waitSemaphoreCount = 1;
  info.pWaitSemaphores = &render_finished_[image];
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain_;
  info.pImageIndices = &image;
  const VkResult r = vkQueuePresentKHR(device_.queue(), &info);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
  check(r, "vkQueuePresentKHR");
  return !suboptimal_;
}

}  // namespace aeroflock::render
