// Draws the flock straight from the simulation's bird buffer (instanced: one instance a bird,
// posed once a frame by the pose pass, pose.comp, from its state; the vertex shader only places the
// mesh by that pose), with the ground, the sky, the branches and, when asked, the target rings and
// routes. Records into a caller's command buffer and colour image, so that a
// window (swapchain images) and headless rendering (an offscreen image) share it.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>

#include "gpu/buffer.h"
#include "gpu/device.h"
#include "model/scenario.h"
#include "render/camera.h"

namespace aeroflock::render {

struct View {
  Camera camera;
  bool show_targets = true;
  float time = 0.0f;               // s, for anything animated independently of the birds
  float scene_distance = 3000.0f;  // cm from the eye to what it looks at: the fog scales with it
  // At most this many birds cast shadows, each for the birds after it up to the next (0: all):
  // the shadows' fill is what costs in a window on the CPU.
  uint32_t shadow_casters = 0;
  // Birds narrower than this (pixels) are drawn with one triangle a wing (tiny_bird_mesh), 0: none.
  // The window's level of detail on a CPU device; pictures draw every bird in full.
  float tiny_pixels = 0.0f;
};

// Towards the sun (world, unit): the light and the birds' shadows.
glm::vec3 sun_direction();

// Samples a pixel unless asked otherwise: 4 (edges and distant birds soft), but none in a window
// drawn on the CPU (lavapipe), where 4 samples cost a third of the frame rate.
uint32_t default_msaa(const gpu::Device& device, bool interactive);
// Whether the device draws on the CPU (lavapipe): the window spares it costly work.
bool is_cpu_device(const gpu::Device& device);

class Renderer {
 public:
  // `color_format`: the images it will draw into (e.g. VK_FORMAT_R8G8B8A8_UNORM offscreen, the
  // swapchain's format in a window); `extent` their size (make a new Renderer on resize). The
  // device must have a graphics queue (gpu::DeviceOptions::graphics).
  // `msaa`: samples a pixel (1, 2, 4, 8), as many of them as the device has.
  Renderer(const gpu::Device& device, const Scenario& scenario, VkFormat color_format,
           VkExtent2D extent, uint32_t msaa = 4);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Records one frame: waits (barrier) for earlier compute writes to `birds`, clears and draws
  // into `color` (any layout before; `final_layout` after: e.g. PRESENT_SRC_KHR or
  // TRANSFER_SRC_OPTIMAL). `birds` holds `bird_count` gpu::GpuBird; `world` gives the targets'
  // positions now and the branches.
  void record(VkCommandBuffer cmd, VkImage color, VkImageView color_view, const gpu::Buffer& birds,
              uint32_t bird_count, const World& world, const View& view,
              VkImageLayout final_layout);

  VkExtent2D extent() const;
  VkFormat format() const;
  uint32_t samples() const;  // a pixel, as drawn

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aeroflock::render
