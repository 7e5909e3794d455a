// The flock stepped by the compute shader (step.comp): every bird one element of a storage
// buffer, a frame's steps in one dispatch, the state read back double-buffered without stalling
// the stepping.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/device.h"
#include "gpu/layout.h"
#include "model/simulation.h"

namespace aeroflock::gpu {

// The most frames step_frames() records in one command buffer (the targets' buffer holds theirs).
inline constexpr uint32_t kFramesPerSubmission = 16;

class GpuSimulation final : public Simulation {
 public:
  // Throws gpu::Error when the flock does not fit the device (naming the limit and the largest
  // flock that fits). `birds_override` as spawn_birds (engine/model/simulation.h) places them.
  GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds);
  GpuSimulation(const Device& device, Scenario scenario, uint32_t birds_override = 0);
  // The same on a device of its own.
  GpuSimulation(std::unique_ptr<Device> device, Scenario scenario, uint32_t birds_override = 0);

  std::string backend() const override { return "vulkan"; }
  std::string device() const override;
  size_t bird_count() const override { return count_; }
  // Records and submits one dispatch of `steps` steps; returns without waiting for it.
  void step(uint32_t steps, bool record_forces = false) override;
  void step_frames(uint32_t frames) override;
  Snapshot snapshot() override;
  Snapshot ready_snapshot() override;
  uint64_t ready_frame() const override;
  void prepare_forces() override;

  const Device& gpu_device() const { return device_; }
  // The birds' state on the device (bird_count() GpuBird), written by the submitted frames: what
  // the renderer draws from, after a compute-to-vertex barrier.
  const Buffer& bird_buffer() const { return birds_; }

 private:
  // What one frame in flight owns: its targets, its readback and its unpacked state.
  struct Slot {
    Buffer targets, readback;  // targets: a frame's at its start, then at the next one's, per frame
    std::unique_ptr<Buffer> forces;      // host copy of the forces, once asked for
    std::unique_ptr<Buffer> perception;  // host copy of the perception, when the flock flocks
    VkDescriptorSet set = VK_NULL_HANDLE, forces_set = VK_NULL_HANDLE, perceive_set = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    Snapshot snapshot;  // its frame, steps and time; the vectors below once unpacked
    bool unpacked = false, has_forces = false;
    std::vector<BirdState> birds;
    std::vector<StepForces> step_forces;
    std::vector<Perception> perception_state;
  };
  // Flocking: the neighbour grid's buffers and passes (grid_*.comp), and perceive.comp.
  struct Flocking {
    GridShape shape;
    Buffer place, counts, starts, blocks, points, keys, owners, ranges, search;
    ComputePipeline count, scan_blocks, scan_totals, ranges_pass, scatter, perceive;
    Flocking(const Device& device, const Scenario& scenario, const std::vector<BirdState>& birds);
  };
  Snapshot read(Slot& slot);
  // Records and submits `frames` frames of `steps` steps each in one command buffer.
  void submit_frames(uint32_t frames, uint32_t steps, bool record_forces);
  void record_perception(VkCommandBuffer cmd, Slot& slot, const StepConstants& c);

  std::unique_ptr<Device> owned_device_;
  const Device& device_;
  uint32_t count_;
  Buffer birds_, species_, routes_, route_targets_, branches_;
  Buffer perception_;  // each bird's GpuPerception (one element when no flock flocks)
  std::unique_ptr<Flocking> flocking_;  // when a flock of the scenario flocks
  ComputePipeline step_;
  // step_forces.comp and the forces it writes, made when a frame first records forces.
  std::unique_ptr<ComputePipeline> step_forces_;
  std::unique_ptr<Buffer> forces_;
  Slot slots_[2];
  int last_ = -1;  // the slot of the last frame (-1: none yet)
  std::vector<BirdState> initial_;
  Submitter submitter_;  // last: destroyed first, waiting for the frames in flight
};

}  // namespace aeroflock::gpu
