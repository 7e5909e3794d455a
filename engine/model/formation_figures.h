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
#include "step.h"
#include "world.h"

namespace aeroflock {

// Where a follower `behind` (cm) another of its species, level at its height, meets the most
// upwash over its wingbeat (upwash_met, its wingbeat in the best phase): the lateral offset of
// centres, cm, to 0.005 spans. The optimum that the model's own vortex spacing predicts.
double best_lateral_offset(const Species& s, double behind);

// One snapshot. A follower is a bird with another at least kFormationBehind spans ahead of it
// along its flight through the air, within kWakeReach spans: the nearest such is the bird it
// follows, in whose frame (its flight through the air, level across: its wings' axis, and its
// wake's) it is measured. `world` gives the wind (none: calm). In a crosswind the bird crabs, and
// its wake trails behind it through the air, not along its track over the ground: measured
// along the track, geese-migration's followers (a 4.8 m/s crosswind at 300 m, a crab of 14
// degrees at 17.5 m/s) seemed to keep a V place 7 % of the time where they kept it 51 %.
struct FormationFigures {
  size_t followers = 0;
  size_t in_v =
      0;  // at a bearing of 30-60 degrees behind the wing, lateral within 10 % of `optimum`
  size_t in_phase =
      0;              // of those in V: phase lag within pi / 4 of 2 pi f dx / U (the wingtip path)
  size_t behind = 0;  // directly behind: lateral within kDirectlyBehind spans (the downwash)
  size_t anti_phase = 0;  // of those: phase lag within pi / 4 of 2 pi f dx / U + pi
};

// A follower whose centre is within a quarter span of its leader's track, across the flight, is
// directly behind it: its body in the downwash between the leader's tip vortices (pi / 8 of the
// span either side).
inline constexpr double kDirectlyBehind = 0.25;

// What a bird is in a snapshot's formation: a head follows none (the formation's heads, and any
// bird flying alone); `none`: not measured (another flock's, or not flocking now).
enum class FormationRole : uint8_t { none, head, follower, in_v };

// `roles`, where given, gets each bird's role (birds.size() of them).
FormationFigures formation_figures(std::span<const BirdState> birds, const Species& s,
                                   double optimum, std::vector<FormationRole>* roles = nullptr,
                                   const World* world = nullptr);

// The snapshot of flock `flock` of `scenario`, over its birds that flock now and are finite;
// `roles` as above, one for each of `birds`.
FormationFigures measure_formation(const Scenario& scenario, const std::vector<BirdState>& birds,
                                   uint32_t flock, double optimum,
                                   std::vector<FormationRole>* roles = nullptr);

// Snapshots summed: the fractions over all of them. And the wings' power (StepForces::power) of
// each role over every frame it is given, each bird in its role at the snapshot before: a
// wingbeat's power swings from below zero to several times its mean, so a snapshot a second would
// not tell a saving of a few per cent.
struct FormationMean {
  double optimum = 0.0;  // cm: best_lateral_offset one span behind
  size_t samples = 0;
  FormationFigures sum;
  double power_sum[3]{};     // erg/s summed: heads, followers (those in V too), those in V
  size_t power_frames[3]{};  // bird-frames summed
  void add(const FormationFigures& f);
  void add_power(std::span<const FormationRole> roles, std::span<const StepForces> forces);
  double followers() const;   // a snapshot's, on average
  double in_v() const;        // of the followers (NaN: none)
  double in_phase() const;    // of those in V (NaN: none)
  double behind() const;      // of the followers, directly behind (NaN: none)
  double anti_phase() const;  // of those directly behind (NaN: none)
  // W, a bird's on average over the frames given (NaN: none)
  double head_power_w() const { return power_w(0); }
  double follower_power_w() const { return power_w(1); }
  double in_v_power_w() const { return power_w(2); }

 private:
  double power_w(int k) const;
};

}  // namespace aeroflock
