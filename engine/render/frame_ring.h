// The window's frames in flight: per frame a command buffer to draw with, a semaphore for the
// swapchain image it draws into and a fence, and GPU timestamps around the simulation's step.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <optional>

#include "gpu/device.h"

namespace aeroflock::render {

class FrameRing {
 public:
  static constexpr uint32_t kFrames = 2;

  explicit FrameRing(const gpu::Device& device);
  ~FrameRing();  // waits for the device to be idle
  FrameRing(const FrameRing&) = delete;
  FrameRing& operator=(const FrameRing&) = delete;

  // Moves to the next frame and waits until its previous use has finished.
  void begin();
  // The semaphore that the swapchain signals when this frame's image is ready.
  VkSemaphore acquired() const { return slots_[slot_].acquired; }

  // Submits a timestamp: the simulation's step for this frame is submitted next.
  void stamp_step_start();
  // Begins this frame's command buffer (with the step's closing timestamp when it was stamped).
  VkCommandBuffer begin_draw();
  // Ends and submits it: waits for acquired() before writing colour, signals `rendered`.
  void submit_draw(VkSemaphore rendered);

  // GPU milliseconds of the last measured step (stamped frames only), once its frame finished.
  std::optional<double> step_ms() const { return step_ms_; }

 private:
  struct Slot {
    VkCommandBuffer draw = VK_NULL_HANDLE;
    VkCommandBuffer stamp = VK_NULL_HANDLE;
    VkSemaphore acquired = VK_NULL_HANDLE;
    VkFence done = VK_NULL_HANDLE;
    bool stamped = false;   // stamp_step_start() in this use of the slot
    bool measured = false;  // both timestamps submitted: read them when the fence is waited for
  };
  void destroy();
  void read_timestamps(uint32_t slot);

  const gpu::Device& device_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;  // 2 a slot; none where the queue has no timestamps
  uint64_t timestamp_mask_ = 0;
  std::array<Slot, kFrames> slots_{};
  uint32_t slot_ = kFrames - 1;
  std::optional<double> step_ms_;
};

}  // namespace aeroflock::render
