#pragma once
// Compute pipelines, the barriers between their work, and submitting it to the queue.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <string_view>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device.h"

namespace aeroflock::gpu {

// One binding of a compute pipeline (set 0; host_device.h names the numbers): a storage buffer,
// or a buffer read as a storage texel buffer of format `texels` (a GLSL imageBuffer, read with
// imageLoad). A CPU device (lavapipe) loads a storage buffer lane by lane, a branch each, wherever
// the invocations may diverge, but loads texels for all its lanes at once, and an image's inline
// (a samplerBuffer's texelFetch is a call, around which every live register is saved: 6 % more
// instructions in the perception): the neighbour search reads the grid that way (perceive.comp).
struct Binding {
  Binding(uint32_t number) : number(number) {}  // a storage buffer
  Binding(uint32_t number, VkFormat texels)
      : number(number), type(VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER), texels(texels) {}
  uint32_t number;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  VkFormat texels = VK_FORMAT_UNDEFINED;  // of a texel buffer
};

// A buffer at a binding number (host_device.h's kBinding...): what a descriptor set is made of.
struct Bound {
  uint32_t binding;
  const Buffer* buffer;
};

// A compute shader with the buffers at `bindings` and a push-constant block of `push_size` bytes
// (0: none). Its pool holds `max_sets` descriptor sets. `constants[i]` specialises the shader's
// 32-bit constant of constant_id i.
class ComputePipeline {
 public:
  ComputePipeline(const Device& device, std::span<const uint32_t> spirv,
                  std::vector<Binding> bindings, uint32_t push_size, uint32_t max_sets = 4,
                  std::vector<uint32_t> constants = {});
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  // A descriptor set from each binding's buffer, named beside it: {kBindingBirds, &birds}, ...
  // Every binding of the pipeline once, in any order (an error names the one missing, extra or
  // twice given). Lives as long as the pipeline, and so do its texel buffers' views.
  VkDescriptorSet make_set(std::span<const Bound> buffers);
  VkDescriptorSet make_set(std::initializer_list<Bound> buffers) {
    return make_set(std::span<const Bound>(buffers.begin(), buffers.size()));
  }
  // make_set, and the set that dispatch() uses without one.
  void set_buffers(std::span<const Bound> buffers) { default_set_ = make_set(buffers); }
  void set_buffers(std::initializer_list<Bound> buffers) { default_set_ = make_set(buffers); }

  // Records bind + push constants + vkCmdDispatch(groups_x, 1, 1). `push_size` must be the
  // pipeline's. Error if groups_x exceeds maxComputeWorkGroupCount[0].
  void dispatch(VkCommandBuffer cmd, uint32_t groups_x, const void* push = nullptr,
                uint32_t push_size = 0) const;
  void dispatch(VkCommandBuffer cmd, VkDescriptorSet set, uint32_t groups_x, const void* push,
                uint32_t push_size) const;

  // Throws Error when a dispatch of `groups_x` work groups exceeds maxComputeWorkGroupCount[0].
  void check_groups(uint32_t groups_x) const;

  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }

 private:
  void destroy();
  void check_range(const Binding& binding, VkDeviceSize bytes) const;

  const Device& device_;
  std::vector<Binding> bindings_;
  uint32_t push_size_;
  std::vector<VkBufferView> views_;  // of the texel buffers in the sets made
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet default_set_ = VK_NULL_HANDLE;
};

// Work groups of `local_size` needed for `items` invocations.
uint32_t group_count(uint64_t items, uint32_t local_size);
// Throws Error unless one dispatch of `items` invocations, `local_size` a work group, fits the
// device's maxComputeWorkGroupCount[0]; the message names the most that fit, e.g. "5000000 birds
// need 78125 work groups of 64 in one dispatch; llvmpipe (...) allows 65535
// (maxComputeWorkGroupCount[0]): at most 4194240 birds".
void check_group_count(const Device& device, uint64_t items, uint32_t local_size,
                       std::string_view what = "birds");

// Barriers (global memory barriers; every earlier compute or transfer write is covered):
// earlier compute/transfer writes -> compute shader reads and writes (and earlier reads before
// later writes). Use between dependent dispatches, at the start of a frame, after an upload copy.
void barrier_to_compute(VkCommandBuffer cmd);
// earlier compute/transfer writes -> transfer reads and writes: before copying results out.
void barrier_to_transfer(VkCommandBuffer cmd);
// earlier compute/transfer writes -> host reads: before the host reads a mapped buffer.
void barrier_to_host(VkCommandBuffer cmd);

// vkCmdCopyBuffer of `size` bytes.
void copy_buffer(VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize size,
                 VkDeviceSize src_offset = 0, VkDeviceSize dst_offset = 0);
// barrier_to_transfer, copy the whole of `src` (at most dst.size(), and at most `size` bytes) to
// `dst`, barrier_to_host: after the fence, dst.mapped() holds src's contents.
void record_readback(VkCommandBuffer cmd, const Buffer& src, const Buffer& dst,
                     VkDeviceSize size = VK_WHOLE_SIZE);

// Owns a command pool on the device's compute queue. Not thread-safe (one thread submits).
//
// Synchronous: run([&](VkCommandBuffer cmd) { ... }) records, submits, waits (setup, tests).
// Asynchronous, `frames` command buffers in turn (double-buffered with frames = 2):
//     VkCommandBuffer cmd = submitter.begin();     // waits for this slot's previous frame only
//     barrier_to_compute(cmd);                      // after the previous frame's work
//     pipeline.dispatch(cmd, groups, &push, sizeof push);
//     record_readback(cmd, state, readback[submitter.frame()]);
//     VkFence done = submitter.submit();
//     ... later: submitter.wait(done); read readback[...]
// Device timestamps a command buffer writes (vkCmdWriteTimestamp), read once it has finished:
// where each pass of a frame begins and ends on the device's own clock (aeroflock bench).
class Timestamps {
 public:
  // Whether the device's queue writes timestamps (its family's timestampValidBits).
  static bool supported(const Device& device);
  Timestamps(const Device& device, uint32_t count);
  ~Timestamps();
  Timestamps(const Timestamps&) = delete;
  Timestamps& operator=(const Timestamps&) = delete;

  // Records the reset of the first `n`, before any is written again.
  void reset(VkCommandBuffer cmd, uint32_t n);
  // Records timestamp `query` once the commands before it have finished.
  void write(VkCommandBuffer cmd, uint32_t query);
  // The first `n` in nanoseconds, from the first; the command buffer that wrote them has finished.
  std::vector<double> read_ns(uint32_t n) const;

 private:
  const Device& device_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint64_t mask_;       // the bits the queue writes
  double ns_per_tick_;  // timestampPeriod
};

class Submitter {
 public:
  explicit Submitter(const Device& device, uint32_t frames = 2);
  ~Submitter();  // waits for the frames in flight
  Submitter(const Submitter&) = delete;
  Submitter& operator=(const Submitter&) = delete;

  void run(const std::function<void(VkCommandBuffer)>& record);

  VkCommandBuffer begin();
  VkFence submit();
  // Slot of the frame being recorded (after begin()) or last submitted: 0..frames-1.
  uint32_t frame() const { return slot_; }
  void wait(VkFence fence) const;
  void wait_all() const;

 private:
  struct Slot {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    bool submitted = false;
  };
  void submit(VkCommandBuffer cmd, VkFence fence) const;
  void destroy();

  const Device& device_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::vector<Slot> slots_;
  uint32_t slot_ = 0;
  bool recording_ = false;
};

}  // namespace aeroflock::gpu
