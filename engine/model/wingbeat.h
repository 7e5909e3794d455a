// Wingbeat kinematics (paper 3.2; docs/MODEL.md replaces the lost Fig. 6) and the wing force
// points.
#pragma once

#include <glm/vec3.hpp>

#include "species.h"

namespace aeroflock {

// Joint angles at wingbeat phase psi, radians. Arm angles relative to the body, hand angles
// relative to the arm. Flapping up > 0, feathering leading edge down > 0, lead-lag forward > 0.
// The arm feathers as B_arm sin(psi) - twist_bias - incidence: twist_bias is its mean incidence,
// `incidence` what the bird adds braking to land. `sweep` is the bird's mean lead-lag (forward
// > 0), its pitch trim: it moves the wings' lift fore and aft.
struct WingbeatAngles {
  double flap_arm, flap_hand, feather_arm, feather_hand, leadlag;
};
WingbeatAngles wingbeat_angles(const Species& s, double phase, double amp, double sweep,
                               double incidence);

// One force point of a wing segment (paper Fig. 9), body frame, relative to the centre of mass.
struct WingPoint {
  glm::dvec3 position;  // cm
  glm::dvec3 velocity;  // cm/s, the point's own motion from the wingbeat
  glm::dvec3 chord;     // unit, towards the leading edge
  glm::dvec3 normal;    // unit, upper surface
  double area;          // cm^2
};

// The right wing's points: [0] the middle of the arm, [1] the middle of the hand. The sweep moves
// slowly against the wingbeat: its rate is left out of the points' velocities.
void right_wing_points(const Species& s, double phase, double amp, double frequency, double sweep,
                       double incidence, WingPoint out[2]);
// Where right_wing_points places the right wing's two points, alone (cheaper: no velocities, no
// feathering; the incidence moves neither).
void right_wing_places(const Species& s, double phase, double amp, double sweep, glm::dvec3 out[2]);
// The right wingtip at phase psi, body frame, relative to the centre of mass, cm (the end of the
// hand, as right_wing_points places it).
glm::dvec3 right_wingtip(const Species& s, double phase, double amp, double sweep);
// The left wing is the right wing mirrored through the body's x-y plane.
WingPoint mirror_to_left(const WingPoint& p);

}  // namespace aeroflock
