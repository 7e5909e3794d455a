#include "run/structure.h"

#include <algorithm>
#include <cmath>

namespace aeroflock {

void StructureObserver::start(Simulation& sim) {
  const Scenario& sc = sim.scenario();
  next_ = window_.from;
  for (uint32_t f = 0; f < sc.flocks.size(); ++f)
    if (sc.flocks[f].flocking) {
      flocking_.push_back(f);
      const Species& s = sc.species[sc.flocks[f].species];
      flocks_.push_back(
          {sc.flocks[f].name, s.name, s.box_c, window_.from, window_.to, window_.every, {}, {}});
      // A flock that meets the wakes, or of a species that flies in formation (its wakes off:
      // the ablation): the optimum a follower one span behind its leader flies at
      // (formation_figures.h).
      if (sc.flocks[f].wake || s.w_formation > 0.0) {
        flocks_.back().formation = FormationMean{best_lateral_offset(s, s.box_c), 0, {}};
        formation_ = true;
      }
    }
  roles_.resize(flocks_.size());
  frame_seconds_ = sc.frame_seconds();
}

bool StructureObserver::wants_forces(uint64_t frame, bool) const {
  return weighs_power(double(frame) * frame_seconds_);
}

bool StructureObserver::weighs_power(double t) const {
  return formation_ && t >= window_.from - 1e-9 && t <= window_.to + 1e-9;
}

bool StructureObserver::due(double t) const {
  // A frame's time is a multiple of its length: the small allowance keeps a sampling time that
  // falls on a frame from missing it to rounding.
  return t >= next_ - 1e-9 && t <= window_.to + 1e-9;
}

void StructureObserver::frame(Simulation& sim, uint64_t) {
  const double t = sim.time();
  if (due(t)) {
    const std::vector<BirdState>& birds = sim.birds();
    for (size_t k = 0; k < flocking_.size(); ++k) {
      if (const auto figures = measure_structure(sim.scenario(), birds, flocking_[k]))
        flocks_[k].structure.add(*figures, t);
      if (auto& formation = flocks_[k].formation)
        formation->add(
            measure_formation(sim.scenario(), birds, flocking_[k], formation->optimum, &roles_[k]));
    }
    // The next sampling time after t, counted from the window's start (no drift, no loop).
    next_ = window_.from +
            (std::floor((t - window_.from) / window_.every + 1e-9) + 1.0) * window_.every;
  }
  // The wings' power of this frame (recorded where wants_forces asked), each bird in its role at
  // the last snapshot. Over many ranks the frame's forces are not gathered: no power then.
  if (weighs_power(t)) {
    const Snapshot s = sim.snapshot();
    if (s.forces && s.forces->size() == s.birds->size() && !s.ids)
      for (size_t k = 0; k < flocking_.size(); ++k)
        if (auto& formation = flocks_[k].formation) formation->add_power(roles_[k], *s.forces);
  }
}

}  // namespace aeroflock
