// Wingbeat-averaged forces of a body held at a fixed attitude and speed: the check of docs/MODEL.md
// that level cruise exists inside Table 1's ranges, and the tool to calibrate the kinematics.
#pragma once

#include <glm/vec3.hpp>

#include "species.h"

namespace aeroflock {

// Both wings' force averaged over one wingbeat at `phases` evenly spaced phases; the body flies
// level along +x at `speed` (cm/s), nose up by `pitch` (rad), not rotating. World frame, dyn:
// x is thrust (> 0 forward), y is lift. `sweep`: the wings' mean lead-lag.
struct WingbeatAverage {
  glm::dvec3 force;   // world frame, dyn: x thrust, y lift
  glm::dvec3 torque;  // body frame, about the centre of mass, dyn cm
};
WingbeatAverage average_wing_force(const Species& s, double speed, double frequency, double amp,
                                   double pitch, double sweep = 0.0, int phases = 120);

}  // namespace aeroflock
