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

// One flock over the ranks of `comm`, each the owner of the birds in its slab, ordered by global id
// (the one-rank index). Before each frame's perception the birds that left the slab move to their
// new owner, then each rank receives as ghosts the birds its own may count among their nearest;
// ghosts are perceived, never stepped. Every simulated second the cuts are moved towards balance
// if the busiest rank holds more than kImbalance times the mean. What steps the birds is the
// backend's: DistributedCpuSimulation, DistributedGpuSimulation (distributed_gpu.h). All ranks of
// `comm` construct it and call step() together (collective).
class DistributedSimulation : public Simulation {
 public:
  static constexpr double kImbalance = 1.05;

  size_t bird_count() const override { return birds_.size(); }
  Snapshot snapshot() override;
  // The start as Simulation's, the first perception among the ghosts by the CPU reference
  // (collective).
  Snapshot start_snapshot() override;
  // The strongest reason any rank has to stop (collective).
  int stops_together(int here) override;
  // Whether every rank stepped the frame (collective).
  bool stepped_together(bool here) override;

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

 protected:
  DistributedSimulation(Scenario scenario, MPI_Comm comm);
  // Every bird, handed to a function one at a time (bird k with global id k), as often as asked.
  using Birds = std::function<void(const std::function<void(uint32_t, const BirdState&)>&)>;
  // Every bird spawned as one rank would (the same seed), or bird k of `all`.
  static Birds spawned(const Scenario& scenario, uint32_t birds_override);
  static Birds given(const std::vector<BirdState>& all);
  // Cuts the world from every bird and keeps this rank's: three passes over them, holding only
  // this rank's birds and the counts per cell.
  void place(const Birds& all);
  // Collective, before a frame's exchanges: every simulated second.
  void rebalance_if_due();
  // The birds that left the slab go to their owner (collective), each with its `extra` (what the
  // backend keeps of a bird beside its state, one per bird in order); birds_, ids_ and `extra`
  // stay ordered by id.
  template <class Extra>
  void migrate(std::vector<Extra>& extra);
  // Each rank says how far past its cuts its birds due at `frame` may see (reach_past_cuts), then
  // every bird that flocks now goes as `make(k)`, a Ghost type with an `id`, to the ranks that
  // look where it is. The ghosts received, ordered by id (collective).
  template <class Ghost, class Make>
  std::vector<Ghost> exchange_ghosts(uint64_t frame, const Make& make);
  // The CPU reference's perception of this rank's birds due at `frame` among the ghosts, into
  // `perception` (one per bird of this rank; the others' entries stay as they were). Collective.
  // In a run whose flocks meet wakes (any_wake) the ghosts carry what a wake follows from too.
  void perceive_with_ghosts(uint64_t frame, std::vector<Perception>& perception);
  // The blind sector a rank assumes when it says how deep past its cuts its birds may see, wider
  // than the species' by this (radians): a backend that perceives in float may see a bird at its
  // edge that the reference does not.
  double blind_margin_ = 0.0;

  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  GridShape shape_;
  Slabs slabs_;
  std::vector<BirdState> birds_;  // this rank's, ordered by id
  std::vector<uint32_t> ids_;     // their global ids
  std::vector<BirdState> kinds_;  // a bird of each species and flocking kind of the whole flock
  std::vector<Perception> perception_;  // this rank's birds' last (flocking)
  std::vector<StepForces> forces_;      // of the next step, when the last frame recorded them
  bool forces_current_ = false;
  bool flocking_ = false;
  bool wakes_ = false;  // some flock meets the wakes (any_wake): its ghosts carry them

 private:
  // perceive_with_ghosts among these ghosts (a vector of a Ghost type, ordered by id).
  template <class Ghosts>
  void perceive_among(uint64_t frame, const Ghosts& ghosts, std::vector<Perception>& perception);
  // How far past its cuts this rank's birds due at `frame` may find one of their nearest.
  Reach reach_past_cuts(uint64_t frame) const;

  std::vector<Perception> start_perception_;  // start_snapshot()'s
  std::vector<StepForces> start_forces_;
  size_t total_ = 0;
  uint64_t checked_second_ = 0;  // the last whole simulated second the balance was checked at
  size_t ghosts_ = 0;
  Reach reach_{0.0, 0.0, 0.0, 0.0};
  Traffic traffic_;
};

// The CPU reference on each rank's own birds, bird for bird the same as CpuSimulation on one.
class DistributedCpuSimulation final : public DistributedSimulation {
 public:
  DistributedCpuSimulation(Scenario scenario, MPI_Comm comm, uint32_t birds_override = 0);
  // Given birds (every rank the same), bird k of `all` with global id k.
  DistributedCpuSimulation(Scenario scenario, MPI_Comm comm, const std::vector<BirdState>& all);

  std::string backend() const override { return "cpu"; }
  std::string device() const override;
  void step(uint32_t steps, bool record_forces = false) override;
};

}  // namespace aeroflock::dist
