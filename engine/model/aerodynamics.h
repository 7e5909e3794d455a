// Quasi-steady lift and drag at a force point (paper eqs. 1, 2; docs/MODEL.md replaces Fig. 8).
#pragma once

#include <glm/vec3.hpp>

#include "species.h"
#include "wingbeat.h"

namespace aeroflock {

// Cl = Cl_max sin(2 alpha), Cd = Cd_0 + (Cd_90 - Cd_0) sin^2(alpha), from sin and cos of alpha.
struct Coefficients {
  double lift, drag;
};
Coefficients coefficients(const Species& s, double sin_alpha, double cos_alpha);
double lift_coefficient(const Species& s, double alpha);
double drag_coefficient(const Species& s, double alpha);

// Force on a flat segment of `area` with unit `chord` (towards the leading edge) and unit upper
// `normal`, in air moving at `air_velocity` relative to it (all in one frame). Blade element:
// the component of the air velocity along the span (chord x normal) is dropped. Drag acts along
// the remaining air velocity, lift perpendicular to it and to the span; alpha > 0 when the air
// meets the lower surface.
glm::dvec3 aerodynamic_force(const Species& s, const glm::dvec3& air_velocity,
                             const glm::dvec3& chord, const glm::dvec3& normal, double area);

// The four wing points' forces (right arm, right hand, left arm, left hand) and their torque about
// the centre of mass, body frame. The air at a point r is body_air - omega x r - the point's own
// wingbeat velocity (body_air: the wind less the body's velocity, in the body frame).
struct WingForces {
  glm::dvec3 force[4];
  glm::dvec3 torque;
};
WingForces wing_forces(const Species& s, double phase, double amp, double frequency, double sweep,
                       double incidence, const glm::dvec3& body_air, const glm::dvec3& omega);
// The same at the right wing's points `right` (right_wing_points), with `induced` (may be null):
// air moving at each point besides (the wakes it meets, body frame, in WingForces::force's order).
WingForces wing_forces_at(const Species& s, const WingPoint right[2], const glm::dvec3& body_air,
                          const glm::dvec3& omega, const glm::dvec3* induced);

// Signed attack angle alpha of the same in-plane air velocity, radians (for tests and export).
double attack_angle(const glm::dvec3& air_velocity, const glm::dvec3& chord,
                    const glm::dvec3& normal);

}  // namespace aeroflock
