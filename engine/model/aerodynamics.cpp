#include "aerodynamics.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "constants.h"
#include "wingbeat.h"

namespace aeroflock {

using glm::dvec3;

Coefficients coefficients(const Species& s, double sin_a, double cos_a) {
  return {s.Cl_max * 2.0 * sin_a * cos_a, s.Cd_0 + (s.Cd_90 - s.Cd_0) * sin_a * sin_a};
}

double lift_coefficient(const Species& s, double alpha) {
  return coefficients(s, std::sin(alpha), std::cos(alpha)).lift;
}

double drag_coefficient(const Species& s, double alpha) {
  return coefficients(s, std::sin(alpha), std::cos(alpha)).drag;
}

double attack_angle(const dvec3& air_velocity, const dvec3& chord, const dvec3& normal) {
  return std::atan2(glm::dot(air_velocity, normal), -glm::dot(air_velocity, chord));
}

dvec3 aerodynamic_force(const Species& s, const dvec3& air_velocity, const dvec3& chord,
                        const dvec3& normal, double area) {
  // In the chord-normal plane: u = -|u| cos(alpha) chord + |u| sin(alpha) normal.
  const double u_chord = glm::dot(air_velocity, chord);
  const double u_normal = glm::dot(air_velocity, normal);
  const double speed2 = u_chord * u_chord + u_normal * u_normal;
  if (!(speed2 > 0.0)) return dvec3{0.0};
  const double speed = std::sqrt(speed2);
  const double sin_a = u_normal / speed;
  const double cos_a = -u_chord / speed;
  const Coefficients c = coefficients(s, sin_a, cos_a);
  const double q_area = 0.5 * kAirDensity * speed2 * area;  // eqs. 1, 2 without the coefficient
  const dvec3 lift_dir =
      chord * sin_a + normal * cos_a;  // the in-plane air direction turned 90 deg
  const dvec3 drag_dir = (chord * -cos_a) + (normal * sin_a);
  return q_area * (c.lift * lift_dir + c.drag * drag_dir);
}

WingForces wing_forces(const Species& s, double phase, double amp, double frequency, double sweep,
                       double incidence, const dvec3& body_air, const dvec3& omega) {
  WingPoint right[2];
  right_wing_points(s, phase, amp, frequency, sweep, incidence, right);
  return wing_forces_at(s, right, body_air, omega, nullptr);
}

WingForces wing_forces_at(const Species& s, const WingPoint right[2], const dvec3& body_air,
                          const dvec3& omega, const dvec3* induced) {
  WingForces out{};
  for (int i = 0; i < 2; ++i) {
    const WingPoint points[2] = {right[i], mirror_to_left(right[i])};
    for (int side = 0; side < 2; ++side) {
      const WingPoint& p = points[side];
      dvec3 air = body_air - glm::cross(omega, p.position) - p.velocity;
      if (induced) air += induced[2 * side + i];
      const dvec3 force = aerodynamic_force(s, air, p.chord, p.normal, p.area);
      out.force[2 * side + i] = force;
      out.torque += glm::cross(p.position, force);
    }
  }
  return out;
}

}  // namespace aeroflock
