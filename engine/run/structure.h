// The flock-structure observer: measures each flock that flocks as the field measures starlings
// (model/flock_structure.h, docs/FIELD.md) at every `every` seconds of simulated time within a
// window of the run, and averages the figures over those snapshots.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "model/flock_structure.h"
#include "run/run_loop.h"

namespace aeroflock {

struct StructureWindow {
  double from = 0.0;                                    // s
  double to = std::numeric_limits<double>::infinity();  // s
  double every = 1.0;                                   // s between snapshots
};

class StructureObserver final : public RunObserver {
 public:
  explicit StructureObserver(StructureWindow window) : window_(window) {}
  void start(Simulation& sim) override;
  // Each snapshot is taken at the first frame at or after its time, from + k every: the frames are
  // stepped one at a time (not in batches), so that it is that frame whatever the flock's size.
  bool reads_every_frame() const override { return true; }
  // A flock that meets the wakes has its wings' power summed over every frame of the window.
  bool wants_forces(uint64_t frame, bool last) const override;
  void frame(Simulation& sim, uint64_t frames) override;
  // Whether a frame at simulated time `t` is one it measures (the next snapshot's).
  bool due(double t) const;
  const std::vector<FlockStructureSummary>& flocks() const { return flocks_; }

 private:
  // Whether a frame at simulated time `t` has its wings' power summed (a flock in formation, t
  // within the window).
  bool weighs_power(double t) const;

  StructureWindow window_;
  double next_ = 0.0;
  std::vector<uint32_t> flocking_;  // the scenario's flocks that flock
  std::vector<FlockStructureSummary> flocks_;
  double frame_seconds_ = 0.0;
  bool formation_ = false;                         // a flock of flocks_ has one
  std::vector<std::vector<FormationRole>> roles_;  // each flock's, at its last snapshot
};

}  // namespace aeroflock
