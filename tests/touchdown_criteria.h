// Issue 40's criteria for a touch-down, the envelope's on either backend: no jump into it (at most
// 1 cm beyond the bird's own flight), and after it the speed falling at no more than 30 m/s^2 and
// the body turning at no more than 90 degrees/s over each 30 ms frame. A bird that hovers onto its
// branch (Species::hover_final) grips where its feet meet the branch point (its path within
// kGripReach stand_height of the perch point) at a mean speed over the ground of at most
// touchdown_speed over the wingbeat (or 100 ms) before it: every preset that perches does.
#pragma once

#include <gtest/gtest.h>

#include "model/constants.h"
#include "model/control.h"
#include "model/envelope.h"

namespace aeroflock {

// A species that lands on the ground (perches = 0, the migrants): its landings glide down to the
// site and touch down on it (route.h: lands_on_ground).
inline bool ground_landing(const EnvelopeResult& r, const Species& species) {
  return r.c.kind == EnvelopeCase::Kind::landing && species.perches == 0.0;
}

// The first touch-down's, on a branch or on the ground (a migrant's landings too: since its legs
// fold until its body rests on the ground and it turns into the wind on them, the goose's 3 of 48
// that did not keep these keep them, docs/MODEL.md "Landing on the ground").
inline void expect_smooth_touchdown(const EnvelopeResult& r, const Species& species) {
  if (!r.touchdown) return;
  const Touchdown& d = *r.touchdown;
  const std::string where = r.c.describe() + (d.on_branch ? ", on the branch" : ", on the ground");
  EXPECT_LE(d.jump, 1.0) << where;
  EXPECT_LE(d.speed_fall, 3000.0) << where;
  EXPECT_LE(d.turn_rate, radians(90.0)) << where;
  if (d.on_branch && hovers(species)) {
    EXPECT_LE(d.reach, kGripReach * species.stand_height) << where;
    EXPECT_LE(d.mean_speed, species.touchdown_speed) << where;
  }
}

}  // namespace aeroflock
