// The tail: bend, twist and opening (paper 4.1, eqs. 9, 10) and where its force acts.
#pragma once

#include <glm/vec3.hpp>

#include "bird.h"
#include "species.h"

namespace aeroflock {

// eq. 10: phi = Ct |max(phi_bend, phi_rot)| + phi_min, the max taken by magnitude. Radians.
double tail_opening(const Species& s, double bend, double twist);
// The tail fully open, as a bird holds it braking to land (paper 4.4): eq. 10 at the largest bend
// or twist.
double open_tail(const Species& s);
// The tail's opening now: eq. 10, or fully open while the bird brakes to land.
double tail_opening(const Species& s, const BirdState& b);
// eq. 9: the fan's area, S_t = pi lr^2 phi / 360 with phi in degrees. cm^2.
double tail_area(const Species& s, double opening);

// The tail's force point, chord and upper normal in the body frame. The tail hangs from the hinge
// at x = -a/2, pitched up by tail_incidence + bend (trailing edge up > 0) and then rolled about
// the body x axis by the twist (right side down > 0). Its force acts at 2/3 lr behind the hinge.
struct TailGeometry {
  glm::dvec3 position, chord, normal;
};
TailGeometry tail_geometry(const Species& s, double bend, double twist);

}  // namespace aeroflock
