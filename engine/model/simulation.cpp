#include "simulation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>

#include <omp.h>

#include "body.h"
#include "constants.h"
#include "step.h"

namespace aeroflock {

using glm::dvec3;

namespace {

// Birds per flock: the scenario's counts, or `total` shared out in proportion to them, the birds
// left by rounding down to the flocks with the largest remainders (the first on a tie).
std::vector<uint32_t> flock_sizes(const Scenario& s, uint32_t total) {
  std::vector<uint32_t> sizes;
  uint64_t sum = 0;
  for (const Flock& f : s.flocks) sum += f.count;
  std::vector<uint64_t> remainder;
  for (const Flock& f : s.flocks) {
    const uint64_t share = uint64_t{total} * f.count;
    sizes.push_back(total == 0 ? f.count : static_cast<uint32_t>(share / sum));
    remainder.push_back(total == 0 ? 0 : share % sum);
  }
  if (total > 0 && !sizes.empty()) {
    uint64_t given = 0;
    for (uint32_t n : sizes) given += n;
    std::vector<size_t> order(sizes.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return remainder[a] > remainder[b]; });
    for (size_t k = 0; given < total; k = (k + 1) % order.size(), ++given) ++sizes[order[k]];
  }
  return sizes;
}

}  // namespace

void next_step_forces(const std::vector<BirdState>& birds, const Scenario& s, const World& world,
                      uint64_t step, const std::vector<Perception>* perception,
                      std::vector<StepForces>& forces) {
  forces.resize(birds.size());
  const int64_t n = static_cast<int64_t>(birds.size());
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(i);
    BirdState b = birds[k];
    step_bird(b, s.species[b.species], world, step, s.dt, &forces[k],
              perception ? &(*perception)[k] : nullptr);
  }
}

std::vector<BirdState> spawn_birds(const Scenario& s, uint32_t birds_override) {
  std::vector<BirdState> birds;
  birds.reserve(spawn_count(s, birds_override));
  for_each_spawned(s, birds_override, [&](uint32_t, const BirdState& b) { birds.push_back(b); });
  return birds;
}

void for_each_spawned(const Scenario& s, uint32_t birds_override,
                      const std::function<void(uint32_t, const BirdState&)>& each) {
  check_takeoff_steps(s, s.dt);  // a rest too long to count is refused, not shortened
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<uint32_t> sizes = flock_sizes(s, birds_override);
  uint32_t index = 0;
  for (size_t fi = 0; fi < s.flocks.size(); ++fi) {
    const Flock& f = s.flocks[fi];
    const Species& sp = s.species[f.species];
    // As dense as the scenario's flock: the box grows with the count.
    const dvec3 extent = spawn_extent(f, sp, sizes[fi], s.world.ground_height);
    for (uint32_t k = 0; k < sizes[fi]; ++k) {
      BirdState b;
      b.species = f.species;
      b.route = f.route;
      b.flock = static_cast<uint32_t>(fi);
      b.flocking = (f.flocking ? kSeesFlock : 0u) | (f.flocking && f.wake ? kFeelsWakes : 0u);
      b.position = f.spawn_centre + extent * dvec3{unit(rng), unit(rng), unit(rng)};
      b.attitude = heading_attitude(f.heading);
      b.frequency = std::clamp(std::isnan(f.frequency) ? 0.5 * (sp.f_min + sp.f_max) : f.frequency,
                               sp.f_min, sp.f_max);
      b.amplitude =
          std::clamp(std::isnan(f.amplitude) ? 0.5 * (sp.amp_min + sp.amp_max) : f.amplitude,
                     sp.amp_min, sp.amp_max);
      b.phase = f.random_phase ? kPi * (unit(rng) + 1.0) : 0.0;
      if (f.standing) {
        b.mode = FlightMode::standing;
        b.position.y = s.world.ground_height + sp.stand_height;
        b.rest_steps = whole_steps(f.takeoff_time, s.dt);
        face_the_wind(b, sp, s.world, kPi);
      } else {
        b.velocity = f.speed * dvec3{std::cos(f.heading), 0.0, std::sin(f.heading)};
      }
      each(index++, b);
    }
  }
}

uint64_t spawn_count(const Scenario& s, uint32_t birds_override) {
  if (birds_override > 0) return birds_override;
  uint64_t count = 0;
  for (const Flock& f : s.flocks) count += f.count;
  return count;
}

Simulation::Simulation(Scenario scenario) : scenario_(std::move(scenario)) {
  scenario_.world.move_targets(0.0);
}

Snapshot Simulation::start_snapshot() {
  if (frames_ > 0) throw std::logic_error("Simulation::start_snapshot after the first step");
  Snapshot s = snapshot();
  const bool flocking = any_flocking(scenario_);
  // What frame 0 perceives: the first frame's perception, from the same state.
  if (flocking)
    perceive(*s.birds, scenario_.species, scenario_.world, 0, 0, scenario_.frame_seconds(),
             grid_shape(scenario_.species, *s.birds), start_perception_);
  next_step_forces(*s.birds, scenario_, scenario_.world, 0, flocking ? &start_perception_ : nullptr,
                   start_forces_);
  s.forces = &start_forces_;
  s.perception = flocking ? &start_perception_ : nullptr;
  return s;
}

double Simulation::frame_start(uint64_t steps) const {
  const uint64_t per_frame = scenario_.steps_per_frame;
  return static_cast<double>(steps / per_frame * per_frame) * scenario_.dt;
}

double Simulation::begin_frame() {
  const double start = frame_start(steps_);
  scenario_.world.move_targets(start);
  ++frames_;
  return start;
}

CpuSimulation::CpuSimulation(Scenario scenario, uint32_t birds_override)
    : Simulation(std::move(scenario)),
      birds_(spawn_birds(this->scenario(), birds_override)),
      grid_(grid_shape(this->scenario().species, birds_)),
      grid_cells_(grid_cells_allowed(this->scenario().species, birds_)) {}

CpuSimulation::CpuSimulation(Scenario scenario, std::vector<BirdState> birds)
    : Simulation(std::move(scenario)),
      birds_(std::move(birds)),
      grid_(grid_shape(this->scenario().species, birds_)),
      grid_cells_(grid_cells_allowed(this->scenario().species, birds_)) {}

std::string CpuSimulation::device() const {
  return "cpu reference (" + std::to_string(omp_get_max_threads()) + " threads)";
}

void CpuSimulation::step(uint32_t steps, bool record_forces) {
  begin_frame();
  const double dt = scenario().dt;
  const uint64_t first = this->steps();
  const World& world = this->world();
  const std::vector<Species>& species = scenario().species;
  const int64_t n = static_cast<int64_t>(birds_.size());
  // The birds see their flock at the frame's start, as they were after the last frame.
  const bool flocking = any_flocking(scenario());
  if (flocking) {
    // The grid's cell suits how far the birds' searches reached last (grid_cell_for); it sets
    // how fast they search, never what they find.
    if (const double cell = grid_cell_for(reach_, grid_cells_); cell > 0.0) grid_.cell = cell;
    reach_ = {};
    perceive(birds_, species, world, frames() - 1, first, scenario().frame_seconds(), grid_,
             perception_, &reach_);
  }
  // Each bird runs all the frame's steps before the next bird: its state stays in cache.
  // Only the birds not retired, once some are (each thread an equal share of those).
  const bool some_retired = !retired_.empty();
  const int64_t stepped = some_retired ? static_cast<int64_t>(active_.size()) : n;
#pragma omp parallel for schedule(static)
  for (int64_t j = 0; j < stepped; ++j) {
    const int64_t i = some_retired ? int64_t(active_[static_cast<size_t>(j)]) : j;
    BirdState& b = birds_[static_cast<size_t>(i)];
    const Species& sp = species[b.species];
    const Perception* seen = flocking ? &perception_[static_cast<size_t>(i)] : nullptr;
    for (uint32_t k = 0; k < steps; ++k) step_bird(b, sp, world, first + k, dt, nullptr, seen);
  }
  end_frame(steps);
  forces_current_ = record_forces;
  if (!record_forces) return;
  record_next_forces(birds_, flocking ? &perception_ : nullptr, forces_);
}

void Simulation::record_next_forces(const std::vector<BirdState>& birds,
                                    const std::vector<Perception>* perception,
                                    std::vector<StepForces>& forces) const {
  World next = world();
  next.move_targets(frame_start(steps_));
  next_step_forces(birds, scenario_, next, steps_, perception, forces);
}

void CpuSimulation::retire(std::span<const uint32_t> birds) {
  if (birds.empty()) return;
  if (retired_.empty()) retired_.assign(birds_.size(), 0);
  for (uint32_t b : birds)
    if (b < retired_.size()) retired_[b] = 1;
  active_.clear();
  for (uint32_t i = 0; i < retired_.size(); ++i)
    if (!retired_[i]) active_.push_back(i);
}

Snapshot CpuSimulation::snapshot() {
  return {frames(),
          this->steps(),
          time(),
          &birds_,
          forces_current_ ? &forces_ : nullptr,
          perception_.empty() ? nullptr : &perception_};
}

}  // namespace aeroflock
