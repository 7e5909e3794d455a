// One flock flown by many MPI ranks, each the owner of the birds in its slab of the world
// (slabs.h), bird for bird the same as CpuSimulation on one (docs/DISTRIBUTED.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <mpi.h>

#include "model/simulation.h"
#include "slabs.h"

namespace aeroflock::dist {

// What a rank did to share its birds, summed since the start.
struct Traffic {
  uint64_t migrants_sent = 0;  // birds handed to another owner
  uint64_t ghosts_sent = 0;    // copies sent for others to perceive
  uint64_t bytes_sent = 0;
  uint64_t rebalances = 0;
  double seconds = 0.0;  // wall time in the exchanges (and the rebalancing's reductions)
};

// One rank's share, for the summary.
struct RankShare {
  int rank = 0;
  uint64_t birds = 0, ghosts = 0;
  Traffic traffic;
};

// The CPU reference on the rank's own birds. Before each frame's perception the birds that left
// the slab move to their new owner, then each rank receives as ghosts the birds within the halo
// of its slab; ghosts are perceived, never stepped. Every simulated second the cuts are moved
// towards balance if the busiest rank holds more than kImbalance times the mean. All ranks of
// `comm` construct it and call step() together (collective).
class DistributedCpuSimulation final : public Simulation {
 public:
  static constexpr double kImbalance = 1.05;

  DistributedCpuSimulation(Scenario scenario, MPI_Comm comm, uint32_t birds_override = 0);
  // Given birds (every rank the same), bird k of `all` with global id k.
  DistributedCpuSimulation(Scenario scenario, MPI_Comm comm, const std::vector<BirdState>& all);

  std::string backend() const override { return "cpu"; }
  std::string device() const override;
  size_t bird_count() const override { return birds_.size(); }
  void step(uint32_t steps, bool record_forces = false) override;
  Snapshot snapshot() override;
  // The start as Simulation's, the first perception among the ghosts (collective).
  Snapshot start_snapshot() override;
  // The strongest reason any rank has to stop (collective).
  int stops_together(int here) override;

  // Birds over all ranks.
  size_t total_birds() const { return total_; }
  // The global id of each of this rank's birds (snapshot().birds[k]'s), ascending.
  const std::vector<uint32_t>& ids() const { return ids_; }
  // Every bird, ordered by global id, on rank `root` (empty elsewhere). Collective.
  std::vector<BirdState> gather(int root = 0) const;
  // Every rank's share on rank `root` (empty elsewhere). Collective.
  std::vector<RankShare> gather_shares(int root = 0) const;
  const Slabs& slabs() const { return slabs_; }
  // Along the cut axis, the birds this rank asked for as ghosts at its last perception: those at
  // [low, low_end) below its slab and [high, high_end) above it (cm; empty where from >= to).
  struct Reach {
    double low, low_end, high, high_end;
    bool holds(double x) const { return (x >= low && x < low_end) || (x >= high && x < high_end); }
  };
  const Reach& reach() const { return reach_; }
  size_t ghost_count() const { return ghosts_; }
  const Traffic& traffic() const { return traffic_; }
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }

 private:
  // Every bird, handed to a function one at a time (bird k with global id k), as often as asked.
  using Birds = std::function<void(const std::function<void(uint32_t, const BirdState&)>&)>;
  // Cuts the world from every bird and keeps this rank's: three passes over them, holding only
  // this rank's birds and the counts per cell.
  void place(const Birds& all);
  // How far past its cuts this rank's birds due at `frame` may find one of their nearest.
  Reach reach_past_cuts(uint64_t frame) const;
  void rebalance_if_due();
  void migrate();
  // Ghosts in, then this rank's birds due at `frame` perceive among them, into `perception`
  // (one per bird of this rank; the others' entries stay as they were).
  void perceive_with_ghosts(uint64_t frame, std::vector<Perception>& perception);

  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  GridShape shape_;
  Slabs slabs_;
  std::vector<BirdState> birds_;  // this rank's, ordered by id
  std::vector<uint32_t> ids_;     // their global ids
  std::vector<Perception> perception_;
  std::vector<StepForces> forces_;  // of the next step, when the last frame recorded them
  bool forces_current_ = false;
  std::vector<Perception> start_perception_;  // start_snapshot()'s
  std::vector<StepForces> start_forces_;
  bool flocking_ = false;
  size_t total_ = 0;
  uint64_t checked_second_ = 0;  // the last whole simulated second the balance was checked at
  size_t ghosts_ = 0;
  Reach reach_{0.0, 0.0, 0.0, 0.0};
  Traffic traffic_;
};

}  // namespace aeroflock::dist
