// The flock stepped by the compute shader: every bird one element of a storage buffer, a frame's
// steps in one dispatch, the state read back double-buffered without stalling the stepping.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec4.hpp>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/device.h"
#include "gpu/layout.h"
#include "model/bird.h"
#include "model/scenario.h"

namespace aeroflock::gpu {

// One step's forces of a bird, as the probe shader writes them (StepForces' total, torque, tail
// and tail torque).
struct ProbeForces {
  glm::vec4 total, torque, tail, tail_torque;
};

class GpuSimulation {
 public:
  // Throws gpu::Error when the flock does not fit the device (naming the limit and the largest
  // flock that fits). `birds` as spawn_birds (engine/model/simulation.h) places them.
  GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds);
  GpuSimulation(const Device& device, Scenario scenario, uint32_t birds_override = 0);

  // Submits one frame (scenario.steps_per_frame steps of dt); returns without waiting for it.
  void step_frame();
  // Submits `steps` steps in one dispatch (tests sample single steps); targets stay where they
  // were at the start of the current frame, as with step_frame.
  void step(uint32_t steps);
  // One step of every bird, waited for, with each bird's forces (for the cross-check tests).
  std::vector<ProbeForces> step_probe();
  // The state after the last submitted frame (waits for that frame only).
  const std::vector<BirdState>& birds();
  // The state after the frame before the last submitted one, and its time. That frame is done or
  // nearly (the last one is queued behind it), so reading it leaves the device busy: exporters
  // read this. Before two frames have been submitted, the state now.
  const std::vector<BirdState>& previous_birds();
  double previous_time() const;

  const Scenario& scenario() const { return scenario_; }
  // The world, its targets where the birds see them now (moved at each frame's start).
  const World& world() const { return scenario_.world; }
  double time() const { return time_; }
  uint64_t steps() const { return steps_; }
  // The birds' state on the device (bird_count() gpu::GpuBird), written by the submitted frames:
  // what the renderer draws from, after a compute-to-vertex barrier.
  const Buffer& bird_buffer() const { return birds_; }
  uint32_t bird_count() const { return count_; }

 private:
  StepConstants constants(uint32_t steps) const;
  void write_targets(uint32_t slot, double time);
  double frame_start() const;

  const Device& device_;
  Scenario scenario_;
  uint32_t count_;
  Buffer birds_, species_, routes_, route_targets_, branches_, probes_;
  Buffer targets_[2];       // one per frame in flight: the host moves targets between frames
  Buffer readback_[2];
  ComputePipeline step_, probe_;
  VkDescriptorSet step_sets_[2], probe_set_;
  std::vector<BirdState> host_birds_;
  VkFence last_frame_ = VK_NULL_HANDLE;
  uint32_t last_slot_ = 0;
  VkFence slot_fence_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};  // each slot's last frame
  double slot_time_[2] = {0.0, 0.0};                          // and its time at the end
  uint64_t frames_in_row_ = 0;  // frames submitted since the last probe or start
  std::vector<BirdState> previous_birds_;
  bool host_current_ = true;
  double time_ = 0.0;
  uint64_t steps_ = 0;
  Submitter submitter_;  // last: destroyed first, waiting for the frames in flight
};

}  // namespace aeroflock::gpu
