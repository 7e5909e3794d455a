// A flock of birds stepped with one fixed dt: the CPU reference backend.
#pragma once

#include <cstdint>
#include <vector>

#include "bird.h"
#include "scenario.h"

namespace aeroflock {

// Places the scenario's birds. `birds_override` > 0 spreads that many birds over the flocks in
// proportion to their counts. Deterministic for a given seed.
std::vector<BirdState> spawn_birds(const Scenario& scenario, uint32_t birds_override = 0);

class Simulation {
 public:
  explicit Simulation(Scenario scenario, uint32_t birds_override = 0);

  // Runs one frame: scenario.steps_per_frame steps of dt over all birds (in parallel).
  void step_frame();
  // Runs a single step of dt (tests).
  void step_once();

  const Scenario& scenario() const { return scenario_; }
  const World& world() const { return scenario_.world; }
  const std::vector<BirdState>& birds() const { return birds_; }
  std::vector<BirdState>& birds() { return birds_; }
  double time() const { return time_; }
  uint64_t steps() const { return steps_; }

 private:
  Scenario scenario_;
  std::vector<BirdState> birds_;
  double time_ = 0.0;
  uint64_t steps_ = 0;
};

}  // namespace aeroflock
