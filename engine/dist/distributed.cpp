#include "distributed.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <stdexcept>
#include <type_traits>

#include <omp.h>
#include <glm/common.hpp>

#include "dist/collectives.h"
#include "dist/exchange.h"
#include "model/constants.h"
#include "model/world.h"

namespace aeroflock::dist {
namespace {

// A bird with its id (gather()).
struct Numbered {
  uint32_t id;
  BirdState bird;
};
// A bird another rank perceives: what perception reads of it (flock.cpp: whether it flocks now
// and is of the flock, where it is and how it flies), 72 bytes instead of the whole state's.
struct Ghost {
  uint32_t id;
  uint32_t flock, flocking, mode, landing_stage;
  uint32_t unused;  // explicit, so that no byte sent is left unset
  glm::dvec3 position, velocity;

  static Ghost of(uint32_t id, const BirdState& b) {
    return {id, b.flock,    b.flocking, uint32_t(b.mode), uint32_t(b.landing_stage),
            0u, b.position, b.velocity};
  }
  // As a state to perceive: the fields perception reads; the rest as a new bird's.
  BirdState bird() const {
    BirdState b;
    b.flock = flock, b.flocking = flocking;
    b.mode = FlightMode(mode), b.landing_stage = LandingStage(landing_stage);
    b.position = position, b.velocity = velocity;
    return b;
  }
};
// A ghost in a run whose flocks meet wakes: also what a neighbour's wake follows from (flock.cpp
// see_wakes: its attitude, lift and wingbeat), 136 bytes.
struct WakeGhost : Ghost {
  glm::dquat attitude;
  double lift, phase, frequency, amplitude;

  static WakeGhost of(uint32_t id, const BirdState& b) {
    return {Ghost::of(id, b), b.attitude, b.lift, b.phase, b.frequency, b.amplitude};
  }
  BirdState bird() const {
    BirdState b = Ghost::bird();
    b.attitude = attitude, b.lift = lift;
    b.phase = phase, b.frequency = frequency, b.amplitude = amplitude;
    return b;
  }
};
static_assert(sizeof(Ghost) == 72 && sizeof(WakeGhost) == 136, "no padding sent unset");
static_assert(std::is_trivially_copyable_v<WakeGhost> && std::is_trivially_copyable_v<Numbered>);

// A cut moves at most this many halos per balance check: a bounded number of birds changes owner
// at once.
constexpr int64_t kCutMoveHalos = 2;

// Where the birds' routes lead: with the birds' own spread, what picks the axis.
std::vector<glm::dvec3> route_points(const World& w) {
  std::vector<glm::dvec3> points;
  for (const Target& t : w.targets) points.push_back(t.centre);
  for (const Branch& b : w.branches) points.push_back(b.point);
  return points;
}

CellCounts count_cells(const Slabs& slabs, const std::vector<BirdState>& birds) {
  std::vector<int64_t> cells;
  cells.reserve(birds.size());
  for (const BirdState& b : birds) cells.push_back(slabs.cell_of(b.position));
  std::sort(cells.begin(), cells.end());
  CellCounts counts;
  for (int64_t c : cells) {
    if (!counts.empty() && counts.back().first == c)
      ++counts.back().second;
    else
      counts.emplace_back(c, 1);
  }
  return counts;
}

}  // namespace

DistributedSimulation::DistributedSimulation(Scenario scenario, MPI_Comm comm)
    : Simulation(std::move(scenario)), comm_(comm) {}

// Every rank places every bird as one rank would (the same seed), cuts the world the same way and
// keeps its own: no communication, the ids are the one-rank indices, and no rank holds more than
// its own birds.
DistributedSimulation::Birds DistributedSimulation::spawned(const Scenario& scenario,
                                                            uint32_t birds_override) {
  return [&scenario, birds_override](const auto& each) {
    for_each_spawned(scenario, birds_override, each);
  };
}

DistributedSimulation::Birds DistributedSimulation::given(const std::vector<BirdState>& all) {
  return [&all](const auto& each) {
    for (uint32_t i = 0; i < all.size(); ++i) each(i, all[i]);
  };
}

DistributedCpuSimulation::DistributedCpuSimulation(Scenario scenario, MPI_Comm comm,
                                                   uint32_t birds_override)
    : DistributedSimulation(std::move(scenario), comm) {
  place(spawned(this->scenario(), birds_override));
}

DistributedCpuSimulation::DistributedCpuSimulation(Scenario scenario, MPI_Comm comm,
                                                   const std::vector<BirdState>& all)
    : DistributedSimulation(std::move(scenario), comm) {
  place(given(all));
}

void DistributedSimulation::place(const Birds& all) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &ranks_);
  flocking_ = any_flocking(scenario());
  wakes_ = any_wake(scenario());
  // First pass: how many, how far they spread, and one bird of each species' flocking kind (the
  // grid's cell follows from which species flock, not from how many birds).
  total_ = 0;
  glm::dvec3 lo{INFINITY}, hi{-INFINITY};
  all([&](uint32_t, const BirdState& b) {
    ++total_;
    lo = glm::min(lo, b.position), hi = glm::max(hi, b.position);
    if (std::none_of(kinds_.begin(), kinds_.end(), [&](const BirdState& k) {
          return k.species == b.species && k.flocking == b.flocking;
        }))
      kinds_.push_back(b);
  });
  shape_ = grid_shape(scenario().species, kinds_);
  double reach = 0.0;
  for (const Species& s : scenario().species) reach = std::max(reach, s.perception_radius);
  std::vector<glm::dvec3> points = route_points(world());
  if (total_ > 0) points.push_back(lo), points.push_back(hi);
  slabs_.axis = longer_axis(points);
  slabs_.cell = shape_.cell;
  // A whole cell more than the radius when it is a whole number of cells: a distance that rounds
  // down to the radius is seen.
  slabs_.halo = flocking_ ? static_cast<int64_t>(std::floor(reach / shape_.cell)) + 1 : 0;
  // Second pass: the birds per cell along the axis, then the cuts.
  std::map<int64_t, uint64_t> per_cell;
  all([&](uint32_t, const BirdState& b) { ++per_cell[slabs_.cell_of(b.position)]; });
  slabs_.cuts = balanced_cuts(CellCounts(per_cell.begin(), per_cell.end()), ranks_, slabs_.halo);
  // Third pass: this rank's own.
  all([&](uint32_t i, const BirdState& b) {
    if (slabs_.owner(slabs_.cell_of(b.position)) == rank_) {
      birds_.push_back(b);
      ids_.push_back(i);
    }
  });
  perception_.resize(birds_.size());
}

std::string DistributedCpuSimulation::device() const {
  return "cpu reference (" + std::to_string(omp_get_max_threads()) + " threads a rank) on " +
         std::to_string(ranks_) + " MPI ranks";
}

void DistributedSimulation::rebalance_if_due() {
  const uint64_t second = static_cast<uint64_t>(std::floor(time()));
  if (second <= checked_second_) return;
  checked_second_ = second;
  const double start = MPI_Wtime();
  const uint64_t mine = birds_.size();
  std::vector<uint64_t> per_rank(static_cast<size_t>(ranks_));
  MPI_Allgather(&mine, 1, MPI_UINT64_T, per_rank.data(), 1, MPI_UINT64_T, comm_);
  if (imbalanced(per_rank, kImbalance)) {
    // Every rank gathers every rank's counts per cell and computes the same cuts.
    const CellCounts local = count_cells(slabs_, birds_);
    const int bytes = static_cast<int>(local.size() * sizeof(CellCounts::value_type));
    std::vector<int> sizes(static_cast<size_t>(ranks_)), at(static_cast<size_t>(ranks_));
    MPI_Allgather(&bytes, 1, MPI_INT, sizes.data(), 1, MPI_INT, comm_);
    int total = 0;
    for (int q = 0; q < ranks_; ++q) at[size_t(q)] = total, total += sizes[size_t(q)];
    CellCounts all(size_t(total) / sizeof(CellCounts::value_type));
    MPI_Allgatherv(local.data(), bytes, MPI_BYTE, all.data(), sizes.data(), at.data(), MPI_BYTE,
                   comm_);
    slabs_.cuts = rebalanced_cuts(slabs_.cuts, merged({std::move(all)}), slabs_.halo,
                                  kCutMoveHalos * std::max<int64_t>(slabs_.halo, 1));
    ++traffic_.rebalances;
  }
  traffic_.seconds += MPI_Wtime() - start;
}

DistributedSimulation::Reach DistributedSimulation::reach_past_cuts(uint64_t frame) const {
  Reach r{0.0, 0.0, 0.0, 0.0};
  if (birds_.empty()) return r;
  const double cell = slabs_.cell;
  const double low = rank_ == 0 ? -INFINITY : double(slabs_.cuts[size_t(rank_) - 1]) * cell;
  const double high = rank_ == ranks_ - 1 ? INFINITY : double(slabs_.cuts[size_t(rank_)]) * cell;
  // A bird's nearest lie within the distance of its k-th nearest among this rank's own birds (or
  // its perception radius, when it has fewer): the ghosts it may count among them lie no deeper
  // past a cut than that distance less its own from the cut. A cell more covers rounding.
  // The birds near a cut, and their own rank's birds they may see: those within two perception
  // radii and a cell of it (in id order, as all of this rank's).
  double radius = 0.0;
  for (const Species& s : scenario().species) radius = std::max(radius, s.perception_radius);
  std::vector<Species> looking = scenario().species;
  for (Species& s : looking) s.blind_angle = std::min(s.blind_angle + blind_margin_, 2.0 * kPi);
  std::vector<BirdState> edge;
  for (const BirdState& b : birds_) {
    const double x = b.position[slabs_.axis];
    if (x - low < 2.0 * radius + cell || high - x < 2.0 * radius + cell) edge.push_back(b);
  }
  if (edge.empty()) return r;
  GridShape local = shape_;
  local.buckets = grid_buckets(edge.size());
  const NeighbourGrid grid(edge, local);
  double deepest_low = -INFINITY, deepest_high = -INFINITY;
  for (uint32_t k = 0; k < edge.size(); ++k) {
    const BirdState& b = edge[k];
    const Species& s = scenario().species[b.species];
    const uint32_t k_nearest = static_cast<uint32_t>(s.neighbours);
    if (!flocks_now(b) || k_nearest == 0 ||
        frame % reaction_frames(s, scenario().frame_seconds()) != 0)
      continue;
    const double x = b.position[slabs_.axis];
    const double margin = s.perception_radius + cell;
    if (x - low >= margin && high - x >= margin) continue;
    const std::vector<uint32_t> near = grid.seen_by(k, looking, wind_at(world(), b.position.y));
    const double reach = near.size() >= k_nearest
                             ? glm::length(edge[near.back()].position - b.position)
                             : s.perception_radius;
    deepest_low = std::max(deepest_low, reach - (x - low));
    deepest_high = std::max(deepest_high, reach - (high - x));
  }
  if (deepest_low > -cell) r.low = low - (deepest_low + cell), r.low_end = low;
  if (deepest_high > -cell) r.high = high, r.high_end = high + (deepest_high + cell);
  return r;
}

void DistributedSimulation::perceive_with_ghosts(uint64_t frame,
                                                 std::vector<Perception>& perception) {
  if (wakes_)
    perceive_among(frame,
                   exchange_ghosts<WakeGhost>(
                       frame, [this](size_t k) { return WakeGhost::of(ids_[k], birds_[k]); }),
                   perception);
  else
    perceive_among(
        frame,
        exchange_ghosts<Ghost>(frame, [this](size_t k) { return Ghost::of(ids_[k], birds_[k]); }),
        perception);
}

template <class Ghosts>
void DistributedSimulation::perceive_among(uint64_t frame, const Ghosts& ghosts,
                                           std::vector<Perception>& perception) {
  // This rank's birds and the ghosts, merged by id.
  std::vector<BirdState> seen;
  std::vector<uint32_t> seen_ids, mine;
  seen.reserve(birds_.size() + ghosts.size());
  seen_ids.reserve(seen.capacity());
  mine.reserve(birds_.size());
  merge_by_id(
      ids_, ghosts,
      [&](size_t k) {
        mine.push_back(static_cast<uint32_t>(seen.size()));
        seen.push_back(birds_[k]), seen_ids.push_back(ids_[k]);
      },
      [&](size_t g) { seen.push_back(ghosts[g].bird()), seen_ids.push_back(ghosts[g].id); });
  GridShape local = shape_;
  local.buckets = grid_buckets(seen.size());
  std::vector<Perception> fresh;
  perceive(seen, seen_ids, mine, scenario().species, world(), frame, steps(),
           scenario().frame_seconds(), local, fresh);
  // perceive() leaves a bird not due now as it was: keep its own perception then.
  perception.resize(birds_.size());
  for (size_t k = 0; k < birds_.size(); ++k) {
    const Species& s = scenario().species[birds_[k].species];
    if (frame % reaction_frames(s, scenario().frame_seconds()) == 0) perception[k] = fresh[k];
  }
}

void DistributedCpuSimulation::step(uint32_t steps, bool record_forces) {
  begin_frame();
  rebalance_if_due();
  migrate(perception_);
  if (flocking_) perceive_with_ghosts(frames() - 1, perception_);
  const double dt = scenario().dt;
  const uint64_t first = this->steps();
  const World& w = world();
  const std::vector<Species>& species = scenario().species;
  const int64_t n = static_cast<int64_t>(birds_.size());
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < n; ++i) {
    BirdState& b = birds_[size_t(i)];
    const Perception* seen = flocking_ ? &perception_[size_t(i)] : nullptr;
    for (uint32_t k = 0; k < steps; ++k)
      step_bird(b, species[b.species], w, first + k, dt, nullptr, seen);
  }
  end_frame(steps);
  forces_current_ = record_forces;
  if (!record_forces) return;
  record_next_forces(birds_, flocking_ ? &perception_ : nullptr, forces_);
}

Snapshot DistributedSimulation::snapshot() {
  return {frames(),
          this->steps(),
          time(),
          &birds_,
          forces_current_ ? &forces_ : nullptr,
          flocking_ ? &perception_ : nullptr,
          &ids_};
}

Snapshot DistributedSimulation::start_snapshot() {
  if (frames() > 0) throw std::logic_error("start_snapshot after the first step");
  // What frame 0 perceives, among the ghosts, as the first frame will (its own copy: the run's
  // perception is untouched).
  if (flocking_) perceive_with_ghosts(0, start_perception_);
  next_step_forces(birds_, scenario(), world(), 0, flocking_ ? &start_perception_ : nullptr,
                   start_forces_);
  Snapshot s = snapshot();
  s.forces = &start_forces_;
  s.perception = flocking_ ? &start_perception_ : nullptr;
  return s;
}

std::vector<RankShare> DistributedSimulation::gather_shares(int root) const {
  return gather_to(root, comm_, std::vector<RankShare>{{rank_, birds_.size(), ghosts_, traffic_}});
}

bool DistributedSimulation::stepped_together(bool here) {
  int mine = here ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm_);
  return all == 1;
}

int DistributedSimulation::stops_together(int here) {
  int strongest = 0;
  MPI_Allreduce(&here, &strongest, 1, MPI_INT, MPI_MAX, comm_);
  return strongest;
}

std::vector<BirdState> DistributedSimulation::gather(int root) const {
  std::vector<Numbered> mine;
  for (size_t k = 0; k < birds_.size(); ++k) mine.push_back({ids_[k], birds_[k]});
  std::vector<Numbered> all = gather_to(root, comm_, mine);
  std::sort(all.begin(), all.end(),
            [](const Numbered& a, const Numbered& b) { return a.id < b.id; });
  std::vector<BirdState> birds;
  for (const Numbered& g : all) birds.push_back(g.bird);
  return birds;
}

}  // namespace aeroflock::dist
