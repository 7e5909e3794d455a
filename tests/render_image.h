// Headless pictures for the tests: a flock drawn offscreen, read back as RGBA.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "gpu/compute.h"
#include "gpu/gpu_simulation.h"
#include "render/offscreen.h"
#include "render/renderer.h"

namespace aeroflock::testing {

struct Image {
  uint32_t width, height;
  std::vector<uint8_t> rgba;
  glm::ivec3 at(int x, int y) const {
    const size_t i = (size_t(y) * width + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2]};
  }
};

// Renders the birds of `sim` as they are, seen by `camera` (the targets and routes too: `targets`),
// `msaa` samples a pixel, birds narrower than `tiny_pixels` drawn tiny (render::View).
inline Image render(const gpu::Device& device, gpu::GpuSimulation& sim,
                    const render::Camera& camera, VkExtent2D size, bool targets = false,
                    uint32_t msaa = 4, float tiny_pixels = 0.0f) {
  render::Renderer renderer(device, sim.scenario(), render::Offscreen::kFormat, size, msaa);
  render::Offscreen target(device, size);
  gpu::Submitter submitter(device, 1);
  render::View view;
  view.camera = camera;
  view.show_targets = targets;
  view.tiny_pixels = tiny_pixels;
  sim.birds();  // the last frame has finished
  submitter.run([&](VkCommandBuffer cmd) {
    renderer.record(cmd, target.image(), target.view(), sim.bird_buffer(), sim.bird_count(),
                    sim.world(), view, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    target.record_copy(cmd);
  });
  return {size.width, size.height, target.pixels()};
}

}  // namespace aeroflock::testing
