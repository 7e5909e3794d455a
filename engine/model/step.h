// One fixed step of one bird: controller, wingbeat, forces, torque, Euler integration.
#pragma once

#include <glm/vec3.hpp>

#include "bird.h"
#include "flock.h"
#include "species.h"
#include "world.h"

namespace aeroflock {

// The forces of one step, for tests, cross-checks and export. World frame unless noted.
struct StepForces {
  glm::dvec3 wing[4]{};  // right arm, right hand, left arm, left hand
  glm::dvec3 tail{0.0};
  glm::dvec3 ground{0.0};  // eq. 15
  glm::dvec3 legs{0.0};    // take-off push
  glm::dvec3 gravity{0.0};
  glm::dvec3 total{0.0};
  glm::dvec3 tail_torque{0.0};  // the tail's r x F_t, body frame, eq. 11
  glm::dvec3 torque{0.0};       // all five points' r x F, body frame: what turns the body
  glm::dvec3 wake_air{0.0};  // the air the wakes it meets move at its four wing points, mean, world
  double power = 0.0;        // erg/s: the wings' forces against their own motion (the wingbeat's
                             // aerodynamic power: what flapping costs the bird)
};

// Advances `bird` by dt: the run's step number `step` (its start is step x dt). `seen`: the
// bird's last perception (flocking), none for a bird that flies its route alone. A step whose
// result is not finite (all_finite) is undone: the bird is quarantined at `step` (FlightMode::
// quarantined, quarantined_step), frozen at its last finite state with no forces from then on.
void step_bird(BirdState& bird, const Species& species, const World& world, uint64_t step,
               double dt, StepForces* forces = nullptr, const Perception* seen = nullptr);

// Turns a standing bird on its legs by at most `most` (rad) towards facing into the wind where it
// heeds the wind (control.h: heeds_wind), since it takes off into it; true once it faces it (the
// turn left within `most`; or it heeds none). A bird that stands still turns at kSettleTurn; one
// set down standing, at once.
bool face_the_wind(BirdState& bird, const Species& species, const World& world, double most);

}  // namespace aeroflock
