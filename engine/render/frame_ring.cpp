#include "render/frame_ring.h"

#include <vector>

#include "gpu/error.h"

namespace aeroflock::render {

using gpu::check;

FrameRing::FrameRing(const gpu::Device& device) : device_(device) {
  VkDevice dev = device.handle();
  try {
    pool_ = device.create_command_pool();

    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(device.physical(), &n, families.data());
    const uint32_t bits = families.at(device.queue_family()).timestampValidBits;
    if (bits > 0) {
      timestamp_mask_ = bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1;
      VkQueryPoolCreateInfo queries{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
      queries.queryType = VK_QUERY_TYPE_TIMESTAMP;
      queries.queryCount = 2 * kFrames;
      check(vkCreateQueryPool(dev, &queries, nullptr, &queries_), "vkCreateQueryPool");
    }

    for (Slot& s : slots_) {
      s.draw = device.allocate_command_buffer(pool_);
      s.stamp = device.allocate_command_buffer(pool_);
      VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
      check(vkCreateSemaphore(dev, &semaphore, nullptr, &s.acquired), "vkCreateSemaphore");
      s.done = device.create_fence(true);  // signalled: the first begin() does not wait
    }
  } catch (...) {
    destroy();
    throw;
  }
}

FrameRing::~FrameRing() {
  vkDeviceWaitIdle(device_.handle());
  destroy();
}

void FrameRing::destroy() {
  VkDevice dev = device_.handle();
  for (Slot& s : slots_) {
    if (s.acquired) vkDestroySemaphore(dev, s.acquired, nullptr);
    if (s.done) vkDestroyFence(dev, s.done, nullptr);
    s = Slot{};
  }
  if (queries_) vkDestroyQueryPool(dev, queries_, nullptr);
  if (pool_) vkDestroyCommandPool(dev, pool_, nullptr);  // frees the command buffers
  queries_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

void FrameRing::begin() {
  slot_ = (slot_ + 1) % kFrames;
  Slot& s = slots_[slot_];
  check(vkWaitForFences(device_.handle(), 1, &s.done, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  if (s.measured) read_timestamps(slot_);
  s.stamped = false;
  s.measured = false;
}

void FrameRing::read_timestamps(uint32_t slot) {
  uint64_t t[2] = {};
  const VkResult r = vkGetQueryPoolResults(device_.handle(), queries_, 2 * slot, 2, sizeof t, t,
                                           sizeof t[0], VK_QUERY_RESULT_64_BIT);
  if (r != VK_SUCCESS) return;  // VK_NOT_READY cannot happen after the fence; skip it anyway
  const uint64_t ticks = ((t[1] & timestamp_mask_) - (t[0] & timestamp_mask_)) & timestamp_mask_;
  step_ms_ = ticks * double(device_.limits().timestampPeriod) * 1e-6;
}

void FrameRing::stamp_step_start() {
  if (!queries_) return;
  Slot& s = slots_[slot_];
  check(vkResetCommandBuffer(s.stamp, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(s.stamp, &begin), "vkBeginCommandBuffer");
  vkCmdResetQueryPool(s.stamp, queries_, 2 * slot_, 2);
  // Written once all earlier work on the queue is done, just before the step's dispatch.
  vkCmdWriteTimestamp(s.stamp, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 2 * slot_);
  check(vkEndCommandBuffer(s.stamp), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &s.stamp;
  check(vkQueueSubmit(device_.queue(), 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
  s.stamped = true;
}

VkCommandBuffer FrameRing::begin_draw() {
  Slot& s = slots_[slot_];
  check(vkResetCommandBuffer(s.draw, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(s.draw, &begin), "vkBeginCommandBuffer");
  // Written once the step submitted before this command buffer is done.
  if (s.stamped)
    vkCmdWriteTimestamp(s.draw, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 2 * slot_ + 1);
  return s.draw;
}

void FrameRing::submit_draw(VkSemaphore rendered) {
  Slot& s = slots_[slot_];
  check(vkEndCommandBuffer(s.draw), "vkEndCommandBuffer");
  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &s.acquired;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &s.draw;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &rendered;
  check(vkResetFences(device_.handle(), 1, &s.done), "vkResetFences");
  check(vkQueueSubmit(device_.queue(), 1, &submit, s.done), "vkQueueSubmit");
  s.measured = s.stamped;
}

}  // namespace aeroflock::render
