#include "trim.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "aerodynamics.h"
#include "constants.h"

namespace aeroflock {

using glm::dvec3;

WingbeatAverage average_wing_force(const Species& s, double speed, double frequency, double amp,
                                   double pitch, double sweep, int phases) {
  const glm::dquat attitude = glm::angleAxis(pitch, dvec3{0.0, 0.0, 1.0});
  const dvec3 body_velocity = glm::conjugate(attitude) * dvec3{speed, 0.0, 0.0};
  dvec3 sum{0.0}, torque{0.0};
  for (int k = 0; k < phases; ++k) {
    const WingForces w = wing_forces(s, 2.0 * kPi * k / phases, amp, frequency, sweep, 0.0,
                                     -body_velocity, dvec3{0.0});
    for (const dvec3& f : w.force) sum += attitude * f;
    torque += w.torque;
  }
  return {sum / static_cast<double>(phases), torque / static_cast<double>(phases)};
}

}  // namespace aeroflock
