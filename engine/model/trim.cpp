#include "trim.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "aerodynamics.h"
#include "constants.h"
#include "wingbeat.h"

namespace aeroflock {

using glm::dvec3;

WingbeatAverage average_wing_force(const Species& s, double speed, double frequency, double amp,
                                   double pitch, int phases) {
  const glm::dquat attitude = glm::angleAxis(pitch, dvec3{0.0, 0.0, 1.0});
  const dvec3 body_velocity = glm::conjugate(attitude) * dvec3{speed, 0.0, 0.0};
  dvec3 sum{0.0}, torque{0.0};
  for (int k = 0; k < phases; ++k) {
    WingPoint right[2];
    right_wing_points(s, 2.0 * kPi * k / phases, amp, frequency, right);
    for (const WingPoint& r : right) {
      for (const WingPoint& p : {r, mirror_to_left(r)}) {
        const dvec3 air = -(body_velocity + p.velocity);
        const dvec3 f = aerodynamic_force(s, air, p.chord, p.normal, p.area);
        sum += attitude * f;
        torque += glm::cross(p.position, f);
      }
    }
  }
  return {sum / static_cast<double>(phases), torque / static_cast<double>(phases)};
}

}  // namespace aeroflock
