#include "wake.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "constants.h"
#include "wingbeat.h"

namespace aeroflock {

using glm::dvec3;

double vortex_span(const Species& s) { return kWakeVortexSpan * s.box_c; }

double wake_circulation(const Species& s, double lift, double airspeed) {
  return airspeed > 0.0 ? lift / (kAirDensity * airspeed * vortex_span(s)) : 0.0;
}

double wake_core(const Species& s) { return kWakeCore * s.box_c; }

dvec3 vortex_place(const Species& s, const WakeSource& src, double distance) {
  const double airspeed = glm::length(src.air_velocity);
  const double age = airspeed > 0.0 ? distance / airspeed : 0.0;
  const double phase = src.phase - 2.0 * kPi * src.frequency * age;  // retarded
  const dvec3 tip = right_wingtip(s, phase, src.amplitude, 0.0);
  return dvec3{0.0, kWakeVortexSpan * tip.y, kWakeVortexSpan * tip.z};
}

namespace {
// The velocity a straight vortex line induces at `r` (from its start), the line running from its
// start along the unit `along` to infinity with `circulation` (right-handed about `along`): Biot-
// Savart, circulation / 4 pi h (1 + cos theta) about the line, h / (h^2 + core^2) for 1 / h
// (a Burnham-Hallock core).
dvec3 half_line(const dvec3& r, const dvec3& along, double circulation, double core) {
  const double length = glm::length(r);
  if (!(length > 0.0)) return dvec3{0.0};
  const double on = glm::dot(r, along);
  const dvec3 across = r - along * on;  // h, perpendicular to the line
  const double h2 = glm::dot(across, across);
  return glm::cross(along, across) *
         (circulation / (4.0 * kPi) * (1.0 + on / length) / (h2 + core * core));
}
}  // namespace

VortexPair vortex_pair(const Species& s, const WakeSource& src, const dvec3& station) {
  VortexPair pair;
  const double airspeed = glm::length(src.air_velocity);
  if (!(airspeed > 0.0) || src.lift == 0.0) return pair;
  pair.back = -src.air_velocity / airspeed;
  const double behind = std::max(glm::dot(station - src.position, pair.back), 0.0);
  const dvec3 place = vortex_place(s, src, behind);
  const dvec3 up = src.attitude * dvec3{0.0, 1.0, 0.0};
  const dvec3 right = src.attitude * dvec3{0.0, 0.0, 1.0};
  pair.right_start = src.position + up * place.y + right * place.z;
  pair.left_start = src.position + up * place.y - right * place.z;
  pair.circulation = wake_circulation(s, src.lift, airspeed);
  pair.core = wake_core(s);
  return pair;
}

dvec3 pair_velocity(const VortexPair& pair, const dvec3& point) {
  if (pair.circulation == 0.0) return dvec3{0.0};
  // The right vortex turns so that it blows down inboard and up outboard of it; the left the
  // other way round.
  return half_line(point - pair.right_start, pair.back, pair.circulation, pair.core) +
         half_line(point - pair.left_start, pair.back, -pair.circulation, pair.core);
}

dvec3 wake_velocity(const Species& s, const WakeSource& src, const dvec3& point) {
  return pair_velocity(vortex_pair(s, src, point), point);
}

}  // namespace aeroflock
