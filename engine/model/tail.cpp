#include "tail.h"

#include <algorithm>
#include <cmath>

#include "constants.h"

namespace aeroflock {

using glm::dvec3;

double tail_opening(const Species& s, double bend, double twist) {
  const double larger = std::fabs(bend) > std::fabs(twist) ? bend : twist;
  return s.Ct * std::fabs(larger) + s.tail_min;
}

double open_tail(const Species& s) { return s.Ct * std::max(s.bend_max, s.rot_max) + s.tail_min; }

double tail_opening(const Species& s, const BirdState& b) {
  return b.mode == FlightMode::landing ? open_tail(s) : tail_opening(s, b.tail_bend, b.tail_twist);
}

double tail_area(const Species& s, double opening) {
  return kPi * s.tail_length * s.tail_length * degrees(opening) / 360.0;
}

TailGeometry tail_geometry(const Species& s, double bend, double twist) {
  const double pitch = s.tail_incidence + bend;
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double ct = std::cos(twist), st = std::sin(twist);
  auto roll = [&](const dvec3& v) { return dvec3{v.x, ct * v.y - st * v.z, st * v.y + ct * v.z}; };
  const dvec3 hinge{-0.5 * s.box_a, 0.0, 0.0};
  const dvec3 trailing{-cp, sp, 0.0};
  return {hinge + roll(trailing) * (2.0 / 3.0 * s.tail_length), roll({cp, -sp, 0.0}),
          roll({sp, cp, 0.0})};
}

}  // namespace aeroflock
