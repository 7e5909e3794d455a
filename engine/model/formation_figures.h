// The figures of a formation as Portugal et al. 2014 measured the ibises' V (issue 43;
// docs/MODEL.md "Formation flying"): where each follower flies behind the bird it follows, and
// whether it flaps in that bird's wingtip path. The tests and `aeroflock run --structure-from`
// measure them so.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "bird.h"
#include "scenario.h"
#include "species.h"

namespace aeroflock {

// Where a follower `behind` (cm) another of its species, level at its height, meets the most
// upwash over its wingbeat (upwash_met, its wingbeat in the best phase): the lateral offset of
// centres, cm, to 0.005 spans. The optimum that the model's own vortex spacing predicts.
double best_lateral_offset(const Species& s, double behind);

// One snapshot. A follower is a bird with another at least kFormationBehind spans ahead of it
// along its flight, within kWakeReach spans: the nearest such is the bird it follows, in whose
// frame (its flight, level across) it is measured.
struct FormationFigures {
  size_t followers = 0;
  size_t in_v =
      0;  // at a bearing of 30-60 degrees behind the wing, lateral within 10 % of `optimum`
  size_t in_phase =
      0;  // of those in V: phase lag within pi / 4 of 2 pi f dx / U (the wingtip path)
};
FormationFigures formation_figures(std::span<const BirdState> birds, const Species& s,
                                   double optimum);

// The snapshot of flock `flock` of `scenario`, over its birds that flock now and are finite.
FormationFigures measure_formation(const Scenario& scenario, const std::vector<BirdState>& birds,
                                   uint32_t flock, double optimum);

// Snapshots summed: the fractions over all of them.
struct FormationMean {
  double optimum = 0.0;  // cm: best_lateral_offset one span behind
  size_t samples = 0;
  FormationFigures sum;
  void add(const FormationFigures& f);
  double followers() const;  // a snapshot's, on average
  double in_v() const;       // of the followers (NaN: none)
  double in_phase() const;   // of those in V (NaN: none)
};

}  // namespace aeroflock
