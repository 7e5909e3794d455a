// The flock stepped by the compute shader (step.comp): every bird one element of a storage
// buffer, a frame's steps in one dispatch (several for a long frame), the state read back
// double-buffered without stalling the stepping.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/device.h"
#include "gpu/grid_table.h"
#include "gpu/layout.h"
#include "model/simulation.h"

namespace aeroflock::gpu {

// The most frames step_frames() records in one command buffer (the targets' buffer holds theirs;
// fewer where so many targets would not fit one storage buffer: frames_per_submission()).
inline constexpr uint32_t kFramesPerSubmission = 16;

// The most steps one dispatch of step.comp takes: a longer frame is split into several (step.glsl),
// which step exactly as one. Lavapipe ends every loop of a shader once its loops together have
// come round 65,535 times (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, one count for a group of
// invocations run as one): the step loop and the landing curve's search (control.glsl:
// landing_progress; run masked even where no bird lands) take 2 a step, so a frame's 32,769th
// step and every one after were silently never taken; a bird's landing adds at most 128 turns
// of the search. 4,096 steps (8,192 turns) leave room for dozens of landings a dispatch, and keep
// a dispatch short for a driver that stops long ones (a watchdog).
inline constexpr uint32_t kMaxStepsPerDispatch = 4096;

class GpuSimulation final : public Simulation {
 public:
  // Throws gpu::Error when the flock does not fit the device (naming the limit and the largest
  // flock that fits). `birds_override` as spawn_birds (engine/model/simulation.h) places them.
  GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds);
  GpuSimulation(const Device& device, Scenario scenario, uint32_t birds_override = 0);
  // The same on a device of its own.
  GpuSimulation(std::unique_ptr<Device> device, Scenario scenario, uint32_t birds_override = 0);
  GpuSimulation(std::unique_ptr<Device> device, Scenario scenario, std::vector<BirdState> birds);
  // One MPI rank's share of a flock (dist/distributed_gpu.h), empty until load(): room for
  // `capacity` birds and ghosts, the neighbour grid's cell and the search as for the whole flock,
  // of which `kinds` holds a bird of each species and flocking kind.
  GpuSimulation(const Device& device, Scenario scenario, const std::vector<BirdState>& kinds,
                uint32_t capacity);

  std::string backend() const override { return "vulkan"; }
  std::string device() const override;
  size_t bird_count() const override { return count_; }
  // Records and submits a frame of `steps` steps (one dispatch, or one per kMaxStepsPerDispatch);
  // returns without waiting for it.
  void step(uint32_t steps, bool record_forces = false) override;
  void step_frames(uint32_t frames) override;
  Snapshot snapshot() override;
  Snapshot ready_snapshot() override;
  uint64_t ready_frame() const override;
  void prepare_forces() override;

  const Device& gpu_device() const { return device_; }
  // The neighbour grid's cell the next submission takes, cm (0 without flocking): it follows how
  // far the searches reached (grid_cell_for).
  double grid_cell() const { return flocking_ ? flocking_->shape.cell : 0.0; }
  // The most steps a dispatch takes (kMaxStepsPerDispatch unless set): tests split frames finer
  // to compare the parts with the whole, or coarser to see a driver's limit caught.
  void set_steps_per_dispatch(uint32_t steps);
  uint32_t steps_per_dispatch() const { return steps_per_dispatch_; }
  // The frames step_frames() records in one command buffer (at most kFramesPerSubmission).
  uint32_t frames_per_submission() const { return frames_per_submission_; }
  // Device time of a frame's passes (time_passes): the neighbour grid's (its clearing, count,
  // prefix sum, scatter, ranges and bounds), the perception's and the steps'. Without flocking the
  // grid and perception take none.
  struct PassTimes {
    uint64_t frame = 0;  // the frame's number, from 1 (Simulation::frames() after it)
    double grid_ms = 0.0, perception_ms = 0.0, steps_ms = 0.0;
  };
  // Times every frame's passes from now on with device timestamps; false where the device's queue
  // writes none (nothing is timed then).
  bool time_passes();
  // Every frame timed so far, in order (waits for the frames in flight).
  const std::vector<PassTimes>& pass_times();
  // Of the neighbour searches so far, one bird's in kReachSample: how many, and how many met a
  // slot of the grid's table that another cell holds and searched again (flock.glsl: search),
  // at about twice the cost. Waits for the frames in flight.
  struct Searches {
    uint64_t sampled = 0, again = 0;
  };
  Searches searches();
  // The birds' state on the device (bird_count() GpuBird), written by the submitted frames: what
  // the renderer draws from, after a compute-to-vertex barrier.
  const Buffer& bird_buffer() const { return birds_; }

  // A share's birds as the device holds them, with their perception (where a flock flocks) and
  // global ids (kGhostBird set for a ghost), in the order of the ids without kGhostBird; at most
  // capacity(). Waits for the frames in flight.
  void load(std::span<const GpuBird> birds, std::span<const GpuPerception> perception,
            std::span<const uint32_t> ids);
  uint32_t capacity() const { return capacity_; }
  // The last frame's state as the device left it (waits for it): bird_count() birds, their
  // perception where a flock flocks, their forces where the frame recorded them (else empty).
  struct Raw {
    std::span<const GpuBird> birds;
    std::span<const GpuPerception> perception;
    std::span<const GpuForces> forces;
  };
  Raw raw();
  // A share made to replace another continues its clock: `steps` and `frames` already flown
  // (before its first step).
  void continue_clock(uint64_t steps, uint64_t frames) { resume_clock(steps, frames); }

 private:
  // What one frame in flight owns: its targets, its readback and its unpacked state.
  // The buffers at world_and()'s bindings (gpu_simulation.cpp) with a slot's `targets`, then
  // `more`.
  std::vector<Bound> world_buffers(const Buffer& targets, std::initializer_list<Bound> more) const;

  struct Slot {
    Buffer targets, readback;  // targets: a frame's at its start, then at the next one's, per frame
    Buffer cut_short;          // the birds whose steps, and whose search, its dispatches cut short
    std::unique_ptr<Timestamps> timestamps;  // kTimestampsPerFrame a frame, once time_passes()
    uint32_t timed_frames = 0;               // its frames' timestamps not yet read
    uint64_t first_frame = 0;                // the number of the first of them
    std::unique_ptr<Buffer> forces;          // host copy of the forces, once asked for
    std::unique_ptr<Buffer> perception;      // host copy of the perception, when the flock flocks
    VkDescriptorSet set = VK_NULL_HANDLE, forces_set = VK_NULL_HANDLE,
                    perceive_set = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    Snapshot snapshot;  // its frame, steps and time; the vectors below once unpacked
    bool unpacked = false, has_forces = false;
    bool counted = false;  // its searches added to searches_
    uint32_t copied = 0;   // the birds its readback holds
    uint64_t loads = 0;    // load() calls before it was submitted
    std::vector<BirdState> birds;
    std::vector<StepForces> step_forces;
    std::vector<Perception> perception_state;
  };
  // Flocking: the neighbour grid's buffers and passes (grid_*.comp), and perceive.comp.
  struct Flocking {
    GridShape shape;  // its buckets: the table's room (the slots its buffers hold)
    // The table's sides now (grid_table_for: fitted to the flocks), its least bits and its room's.
    GridTable table;
    uint32_t least_bits = 0, most_bits = 0;
    // The cells the grid may take (grid_cells_allowed; shape.cell one of them) and the search's
    // order for each in `search` (where it begins, and the cells a part's list holds).
    std::vector<double> cells;
    std::vector<uint32_t> search_first, search_cells;
    // Which of `cells` the grid has now.
    size_t cell_index() const;
    Buffer place, counts, starts, blocks, points, keys, owners, cell_boxes, seen, search;
    ComputePipeline count, scan_blocks, scan_totals, scatter, cells_pass, perceive;
    // For up to `capacity` birds of the kinds of `kinds`.
    Flocking(const Device& device, const Scenario& scenario, const std::vector<BirdState>& kinds,
             uint32_t capacity);
  };
  GpuSimulation(const Device& device, Scenario scenario, std::vector<BirdState> birds,
                const std::vector<BirdState>* kinds, uint32_t capacity);
  Snapshot read(Slot& slot);
  // Throws Error when the finished submission of `slot` had birds' steps or neighbour search cut
  // short by the device.
  void check_cut_short(const Slot& slot) const;
  // Fits the grid's cell to how far the searches of `slot`'s finished submission reached.
  void fit_grid_cell(const Slot& slot);
  // Fits the grid's table's sides to how far the flocks of `birds` span, in the grid's cells.
  void fit_grid_table(std::span<const GpuBird> birds);
  // Records and submits `frames` frames of `steps` steps each in one command buffer.
  void submit_frames(uint32_t frames, uint32_t steps, bool record_forces);
  // With `timestamps`, writes `first` + 1 after the grid's passes and `first` + 2 after the
  // perception.
  void record_perception(VkCommandBuffer cmd, Slot& slot, const StepConstants& c,
                         Timestamps* timestamps, uint32_t first);
  // Adds what the finished submission of `slot` measured: its timed frames to pass_times_, its
  // sampled searches to searches_ (once).
  void collect(Slot& slot);
  void collect_all();  // both slots', once their submissions have finished

  std::unique_ptr<Device> owned_device_;
  const Device& device_;
  uint32_t count_, capacity_;
  Buffer birds_, ids_, species_, routes_, route_targets_, branches_;
  Buffer perception_;  // each bird's GpuPerception (one element when no flock flocks)
  std::unique_ptr<Flocking> flocking_;     // when a flock of the scenario flocks
  std::vector<uint32_t> model_constants_;  // what the birds can reach (layout.h)
  ComputePipeline step_;
  uint32_t frames_per_submission_;
  // step_forces.comp and the forces it writes, made when a frame first records forces.
  std::unique_ptr<ComputePipeline> step_forces_;
  std::unique_ptr<Buffer> forces_;
  Slot slots_[2];
  int last_ = -1;  // the slot of the last frame (-1: none yet)
  uint32_t steps_per_dispatch_ = kMaxStepsPerDispatch;
  std::vector<PassTimes> pass_times_;
  Searches searches_;
  uint64_t loads_ = 0;  // load() calls so far
  std::vector<BirdState> initial_;
  Submitter submitter_;  // last: destroyed first, waiting for the frames in flight
};

}  // namespace aeroflock::gpu
