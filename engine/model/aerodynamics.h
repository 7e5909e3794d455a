// Quasi-steady lift and drag at a force point (paper eqs. 1, 2; MODEL.md replaces Fig. 8).
#pragma once

#include <glm/vec3.hpp>

#include "species.h"

namespace aeroflock {

// Cl = Cl_max sin(2 alpha), Cd = Cd_0 + (Cd_90 - Cd_0) sin^2(alpha).
double lift_coefficient(const Species& s, double alpha);
double drag_coefficient(const Species& s, double alpha);

// Force on a flat segment of `area` with unit `chord` (towards the leading edge) and unit upper
// `normal`, in air moving at `air_velocity` relative to it (all in one frame). Blade element:
// the component of the air velocity along the span (chord x normal) is dropped. Drag acts along
// the remaining air velocity, lift perpendicular to it and to the span; alpha > 0 when the air
// meets the lower surface.
glm::dvec3 aerodynamic_force(const Species& s, const glm::dvec3& air_velocity,
                             const glm::dvec3& chord, const glm::dvec3& normal, double area);

// Signed attack angle alpha of the same in-plane air velocity, radians (for tests and export).
double attack_angle(const glm::dvec3& air_velocity, const glm::dvec3& chord,
                    const glm::dvec3& normal);

}  // namespace aeroflock
