// A flock that steps with one fixed dt. Simulation is what the command line, the benchmark, the
// exporters, the renderers and the tests hold; CpuSimulation (here, the reference) and
// gpu::GpuSimulation (the compute shaders) implement it.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bird.h"
#include "flock.h"
#include "scenario.h"
#include "step.h"

namespace aeroflock {

// Places the scenario's birds. `birds_override` > 0 spreads that many birds over the flocks in
// proportion to their counts, each flock's spawn box scaled to keep its density. Deterministic for
// a given seed. Throws std::invalid_argument for a standing flock's takeoff_time too late to count
// in steps (check_takeoff_steps).
std::vector<BirdState> spawn_birds(const Scenario& scenario, uint32_t birds_override = 0);
// The same birds handed to `each` one at a time (bird k, as spawn_birds' k-th), none kept: a
// process that keeps only some of a very large flock (dist/) never holds it all.
void for_each_spawned(const Scenario& scenario, uint32_t birds_override,
                      const std::function<void(uint32_t, const BirdState&)>& each);
// The number of birds spawn_birds places, without placing them.
uint64_t spawn_count(const Scenario& scenario, uint32_t birds_override = 0);

// The forces of each of `birds`' next step at step number `step`, with the targets of `world` and
// their `perception` (null: a scenario without flocking); the birds stay as they are.
void next_step_forces(const std::vector<BirdState>& birds, const Scenario& scenario,
                      const World& world, uint64_t step, const std::vector<Perception>* perception,
                      std::vector<StepForces>& forces);

// One frame's state as an exporter or a renderer reads it. The vectors belong to the simulation
// and stay valid until its next step().
struct Snapshot {
  uint64_t frame = 0;  // step() calls that led to this state (0: the start)
  uint64_t steps = 0;  // steps of dt per bird
  double time = 0.0;   // simulated seconds
  const std::vector<BirdState>* birds = nullptr;
  // Each bird's forces of the step it takes next from this state, computed by the backend that
  // flies it; null unless the frame was stepped with record_forces.
  const std::vector<StepForces>* forces = nullptr;
  // Each bird's last perception (what it saw at the start of this state's frame: docs/MODEL.md
  // "Flocking"); null unless a flock of the scenario flocks.
  const std::vector<Perception>* perception = nullptr;
  // Each bird's global id, ascending, where `birds` are one rank's share of a flock over many
  // (dist/); null: bird k is bird k.
  const std::vector<uint32_t>* ids = nullptr;
};

class Simulation {
 public:
  explicit Simulation(Scenario scenario);
  virtual ~Simulation() = default;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  virtual std::string backend() const = 0;  // as given to --backend: "cpu", "vulkan"
  virtual std::string device() const = 0;   // what runs it, in words
  virtual size_t bird_count() const = 0;

  // Steps every bird `steps` times (0 is allowed) as one frame: targets stay where they were at
  // the frame's start (they move between frames). With `record_forces` the frame's snapshot
  // carries each bird's forces of its next step. On a device it returns before the work is done.
  virtual void step(uint32_t steps, bool record_forces = false) = 0;
  // One frame of the scenario: steps_per_frame steps.
  void step_frame(bool record_forces = false) { step(scenario_.steps_per_frame, record_forces); }
  // `frames` frames of the scenario, the same as as many step_frame() calls. A device records
  // several of them in one submission: a small flock is then not bound by each submission's
  // overhead, but only a submission's last frame is read back (ready_snapshot() gives one).
  virtual void step_frames(uint32_t frames) {
    for (uint32_t f = 0; f < frames; ++f) step_frame();
  }

  // The state after the last step() (on a device, waits for it).
  virtual Snapshot snapshot() = 0;
  // The newest state that can be read without waiting for the device: on the CPU the last; on a
  // device the frame before the last, done or nearly while the last one runs (before two frames,
  // the last, waited for). Exporters take this, so that the simulation never stalls for them.
  virtual Snapshot ready_snapshot() { return snapshot(); }
  // The frame ready_snapshot() would return, without reading it.
  virtual uint64_t ready_frame() const { return frames_; }
  // These birds' flights are over (a judge has its verdict on them): a backend may stop stepping
  // them, their states then staying as they are. For birds that fly alone (the flight envelope's):
  // a flock's others would still see them where they stopped. The CPU reference stops; the
  // compute shaders step every bird still.
  virtual void retire(std::span<const uint32_t> birds) { (void)birds; }
  // Makes ready to record forces (on a device: allocates their buffers, throwing gpu::Error when
  // the device cannot hold them), so that a run that will export fails before it starts.
  virtual void prepare_forces() {}
  const std::vector<BirdState>& birds() { return *snapshot().birds; }
  // Whether the run stops now and why: `here` is this part's reason (0: go on; the run loop's
  // codes, the larger the stronger). One flown by several processes (dist/) stops on the frame
  // any of them must, for the strongest reason any has, asked of all together. Alone, `here`.
  virtual int stops_together(int here) { return here; }
  // Whether every part stepped the frame (`here`: this one did), asked of all together after each
  // frame: one that failed in its step skips the observers, whose calls may be collective, and so
  // must every other. Alone, `here`.
  virtual bool stepped_together(bool here) { return here; }
  // The state before the first step (frame 0, t = 0) with each bird's forces of its first step
  // and what it perceives first, evaluated by the CPU reference from the backend's own state:
  // an export's t = 0 frame. Only before the first step (std::logic_error after it).
  virtual Snapshot start_snapshot();

  const Scenario& scenario() const { return scenario_; }
  // The world, its targets where the birds see them now.
  const World& world() const { return scenario_.world; }
  double time() const { return static_cast<double>(steps_) * scenario_.dt; }
  uint64_t steps() const { return steps_; }
  uint64_t frames() const { return frames_; }

 protected:
  // Called by step() before the work: moves the targets to the frame's start and counts the
  // frame; the start time of the frame.
  double begin_frame();
  // When the frame that starts after `steps` steps per bird starts (targets move then).
  double frame_start(uint64_t steps) const;
  // Called by step() after the work is submitted.
  void end_frame(uint32_t steps) { steps_ += steps; }
  // A simulation that takes over another's birds mid-run goes on from its clock (before its own
  // first step).
  void resume_clock(uint64_t steps, uint64_t frames) { steps_ = steps, frames_ = frames; }
  // After a frame stepped with record_forces: the forces of each of `birds`' next step, with the
  // targets where it will see them (the next frame's start) and its `perception` (null: none).
  void record_next_forces(const std::vector<BirdState>& birds,
                          const std::vector<Perception>* perception,
                          std::vector<StepForces>& forces) const;

 private:
  Scenario scenario_;
  uint64_t steps_ = 0;
  uint64_t frames_ = 0;
  std::vector<StepForces> start_forces_;  // start_snapshot()'s
  std::vector<Perception> start_perception_;
};

// The CPU reference: every bird stepped in double precision, in parallel with OpenMP.
class CpuSimulation final : public Simulation {
 public:
  explicit CpuSimulation(Scenario scenario, uint32_t birds_override = 0);
  CpuSimulation(Scenario scenario, std::vector<BirdState> birds);

  std::string backend() const override { return "cpu"; }
  std::string device() const override;
  size_t bird_count() const override { return birds_.size(); }
  void step(uint32_t steps, bool record_forces = false) override;
  Snapshot snapshot() override;

  // The state, to change between steps (tests).
  std::vector<BirdState>& state() { return birds_; }
  // The neighbour grid's cell its last perception searched (before one, grid_shape's), cm.
  double grid_cell() const { return grid_.cell; }
  void retire(std::span<const uint32_t> birds) override;

 private:
  std::vector<BirdState> birds_;
  std::vector<StepForces> forces_;
  std::vector<Perception> perception_;
  GridShape grid_;                  // the neighbour grid's
  std::vector<double> grid_cells_;  // the cells it may take (grid_cells_allowed)
  SearchReach reach_;               // how far the last perception's searches reached
  bool forces_current_ = false;
  std::vector<uint8_t> retired_;  // per bird, once one is retired
  std::vector<uint32_t> active_;  // the birds stepped then: the others, in order
};

}  // namespace aeroflock
