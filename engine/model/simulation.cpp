#include "simulation.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "body.h"
#include "constants.h"
#include "step.h"

namespace aeroflock {

using glm::dvec3;

namespace {

// Birds per flock: the scenario's counts, or `total` shared out in proportion to them.
std::vector<uint32_t> flock_sizes(const Scenario& s, uint32_t total) {
  std::vector<uint32_t> sizes;
  uint64_t sum = 0;
  for (const Flock& f : s.flocks) sum += f.count;
  for (const Flock& f : s.flocks)
    sizes.push_back(total == 0 ? f.count : static_cast<uint32_t>(uint64_t{total} * f.count / sum));
  if (total > 0 && !sizes.empty()) {
    uint64_t given = 0;
    for (uint32_t n : sizes) given += n;
    for (size_t i = 0; given < total; i = (i + 1) % sizes.size(), ++given) ++sizes[i];
  }
  return sizes;
}

}  // namespace

std::vector<BirdState> spawn_birds(const Scenario& s, uint32_t birds_override) {
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<uint32_t> sizes = flock_sizes(s, birds_override);
  std::vector<BirdState> birds;
  for (size_t fi = 0; fi < s.flocks.size(); ++fi) {
    const Flock& f = s.flocks[fi];
    const Species& sp = s.species[f.species];
    // A flock of many birds with no spawn box gets one: about a wing length between birds.
    dvec3 extent = f.spawn_extent;
    if (sizes[fi] > 1 && extent == dvec3{0.0})
      extent = dvec3{2.0 * sp.wing_length * std::cbrt(static_cast<double>(sizes[fi]))};
    for (uint32_t k = 0; k < sizes[fi]; ++k) {
      BirdState b;
      b.species = f.species;
      b.route = f.route;
      b.position = f.spawn_centre + extent * dvec3{unit(rng), unit(rng), unit(rng)};
      b.attitude = heading_attitude(f.heading);
      b.frequency = std::clamp(std::isnan(f.frequency) ? 0.5 * (sp.f_min + sp.f_max) : f.frequency,
                               sp.f_min, sp.f_max);
      b.amplitude = std::clamp(std::isnan(f.amplitude) ? 0.5 * (sp.amp_min + sp.amp_max) : f.amplitude,
                               sp.amp_min, sp.amp_max);
      b.phase = f.random_phase ? kPi * (unit(rng) + 1.0) : 0.0;
      if (f.standing) {
        b.mode = FlightMode::standing;
        b.position.y = s.world.ground_height + sp.stand_height;
        b.takeoff_time = f.takeoff_time;
      } else {
        b.velocity = f.speed * dvec3{std::cos(f.heading), 0.0, std::sin(f.heading)};
      }
      birds.push_back(b);
    }
  }
  return birds;
}

Simulation::Simulation(Scenario scenario, uint32_t birds_override)
    : scenario_(std::move(scenario)), birds_(spawn_birds(scenario_, birds_override)) {
  scenario_.world.move_targets(0.0);
}

void Simulation::step_frame() {
  const uint32_t steps = scenario_.steps_per_frame;
  const double dt = scenario_.dt;
  const double t0 = time_;
  scenario_.world.move_targets(t0);
  const World& world = scenario_.world;
  const int64_t n = static_cast<int64_t>(birds_.size());
  // Each bird runs all the frame's steps before the next bird: its state stays in cache.
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < n; ++i) {
    BirdState& b = birds_[static_cast<size_t>(i)];
    const Species& sp = scenario_.species[b.species];
    for (uint32_t k = 0; k < steps; ++k) step_bird(b, sp, world, t0 + k * dt, dt);
  }
  steps_ += steps;
  time_ = t0 + steps * dt;
}

void Simulation::step_once() {
  // Targets move between frames, as in step_frame.
  if (steps_ % scenario_.steps_per_frame == 0) scenario_.world.move_targets(time_);
  for (BirdState& b : birds_)
    step_bird(b, scenario_.species[b.species], scenario_.world, time_, scenario_.dt);
  ++steps_;
  time_ += scenario_.dt;
}

}  // namespace aeroflock
