#include "aerodynamics.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "constants.h"

namespace aeroflock {

using glm::dvec3;

double lift_coefficient(const Species& s, double alpha) { return s.Cl_max * std::sin(2 * alpha); }

double drag_coefficient(const Species& s, double alpha) {
  const double sa = std::sin(alpha);
  return s.Cd_0 + (s.Cd_90 - s.Cd_0) * sa * sa;
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
  const double cl = s.Cl_max * 2.0 * sin_a * cos_a;
  const double cd = s.Cd_0 + (s.Cd_90 - s.Cd_0) * sin_a * sin_a;
  const double q_area = 0.5 * kAirDensity * speed2 * area;  // eqs. 1, 2 without the coefficient
  const dvec3 lift_dir = chord * sin_a + normal * cos_a;    // the in-plane air direction turned 90 deg
  const dvec3 drag_dir = (chord * -cos_a) + (normal * sin_a);
  return q_area * (cl * lift_dir + cd * drag_dir);
}

}  // namespace aeroflock
