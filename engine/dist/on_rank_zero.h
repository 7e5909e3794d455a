// Observers that need every bird (the pictures, the flock's structure) in a run over many ranks:
// the birds are gathered on rank 0, where the observer sees them as one simulation
// (docs/DISTRIBUTED.md).
#pragma once

#include <functional>
#include <vector>

#include "dist/distributed.h"
#include "run/run_loop.h"

namespace aeroflock::dist {

// Every bird of a DistributedSimulation, ordered by global id, on rank 0 (none elsewhere), as a
// Simulation at the same frame: what an observer of one process reads. It is not stepped.
class GatheredFlock final : public Simulation {
 public:
  // Gathers the start (collective).
  explicit GatheredFlock(DistributedSimulation& flock);
  // Gathers the birds as they are now and catches up with the flock's frames (collective).
  void refresh();

  std::string backend() const override { return flock_.backend(); }
  std::string device() const override { return flock_.device(); }
  // Every bird (on every rank: what the run has, for a picture's checks).
  size_t bird_count() const override { return flock_.total_birds(); }
  void step(uint32_t, bool) override;
  Snapshot snapshot() override;

 private:
  DistributedSimulation& flock_;
  std::vector<BirdState> birds_;
};

// Runs `inner` on the gathered flock: every rank gathers at the start, at the end and before each
// frame `reads` says (by the frame's simulated time; null: none between), and `inner` (rank 0's
// observer, or one every rank has: it then sees no birds elsewhere) is handed it. `reads` must
// answer alike on every rank. Its stop reason is rank 0's; the run loop makes it every rank's
// (Simulation::stops_together).
class OnRankZero final : public RunObserver {
 public:
  OnRankZero(GatheredFlock& flock, RunObserver* inner, std::function<bool(double)> reads)
      : flock_(flock), inner_(inner), reads_(std::move(reads)) {}
  void start(Simulation&) override;
  bool reads_every_frame() const override { return true; }
  void frame(Simulation&, uint64_t frames) override;
  std::string stop_reason() const override { return inner_ ? inner_->stop_reason() : ""; }
  void finish(Simulation&) override;

 private:
  GatheredFlock& flock_;
  RunObserver* inner_;
  std::function<bool(double)> reads_;
};

}  // namespace aeroflock::dist
