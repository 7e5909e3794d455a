#include "dist/on_rank_zero.h"

#include <stdexcept>

namespace aeroflock::dist {

GatheredFlock::GatheredFlock(DistributedSimulation& flock)
    : Simulation(flock.scenario()), flock_(flock) {
  refresh();
}

void GatheredFlock::refresh() {
  birds_ = flock_.gather();
  // The same frames, each begun and ended as the flock's (its targets moved with it).
  while (frames() < flock_.frames()) {
    begin_frame();
    end_frame(scenario().steps_per_frame);
  }
}

void GatheredFlock::step(uint32_t, bool) {
  throw std::logic_error("GatheredFlock is a view of a flock over ranks: it is not stepped");
}

Snapshot GatheredFlock::snapshot() {
  Snapshot s;
  s.frame = frames();
  s.steps = steps();
  s.time = time();
  s.birds = &birds_;
  return s;
}

void OnRankZero::start(Simulation&) {
  flock_.refresh();
  if (inner_) inner_->start(flock_);
}

void OnRankZero::frame(Simulation& sim, uint64_t frames) {
  if (!reads_ || !reads_(sim.time())) return;
  flock_.refresh();
  if (inner_) inner_->frame(flock_, frames);
}

void OnRankZero::finish(Simulation&) {
  flock_.refresh();
  if (inner_) inner_->finish(flock_);
}

}  // namespace aeroflock::dist
