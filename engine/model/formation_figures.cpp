#include "formation_figures.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "constants.h"
#include "flock.h"
#include "flock_geometry.h"

namespace aeroflock {

using glm::dvec3;

double best_lateral_offset(const Species& s, double behind) {
  BirdState b;
  b.frequency = 0.5 * (s.f_min + s.f_max);
  b.amplitude = 0.8;
  b.velocity = dvec3{1000.0, 0.0, 0.0};
  Perception p;
  p.wakes = 1;
  WakeSource& w = p.wake[0];
  w.air_velocity = b.velocity;
  w.lift = s.mass * kGravity;
  w.frequency = b.frequency;
  w.amplitude = b.amplitude;
  double best = -std::numeric_limits<double>::infinity(), at = 0.0;
  for (int k = 0; k <= 300; ++k) {
    const double lateral = 0.005 * k * s.box_c;
    b.position = dvec3{-behind, 0.0, lateral};
    double most = -std::numeric_limits<double>::infinity();  // over its phase
    for (int m = 0; m < 24; ++m)
      most = std::max(most,
                      upwash_met(s, b, p, dvec3{0.0, 1.0, 0.0}, dvec3{0.0}, 2.0 * kPi * m / 24.0));
    if (most > best) best = most, at = lateral;
  }
  return at;
}

FormationFigures formation_figures(std::span<const BirdState> birds, const Species& s,
                                   double optimum) {
  FormationFigures out;
  for (size_t i = 0; i < birds.size(); ++i) {
    const BirdState& b = birds[i];
    const double own = glm::length(b.velocity);
    if (!(own > 0.0)) continue;
    const dvec3 ahead_b = b.velocity / own;
    const BirdState* lead = nullptr;
    double nearest = kWakeReach * s.box_c;
    for (size_t j = 0; j < birds.size(); ++j) {
      const dvec3 offset = birds[j].position - b.position;
      const double d = glm::length(offset);
      if (j != i && glm::dot(offset, ahead_b) >= kFormationBehind * s.box_c && d <= nearest)
        nearest = d, lead = &birds[j];
    }
    if (!lead) continue;
    const double speed = glm::length(lead->velocity);
    const dvec3 across = glm::cross(lead->velocity, dvec3{0.0, 1.0, 0.0});
    if (!(speed > 0.0) || !(glm::length(across) > 0.0)) continue;
    ++out.followers;
    const dvec3 ahead = lead->velocity / speed;
    const dvec3 side = glm::normalize(across);
    const dvec3 offset = b.position - lead->position;
    const double dx = -glm::dot(offset, ahead), dy = std::fabs(glm::dot(offset, side));
    const double bearing = std::atan2(dx, dy);
    if (bearing < kPi / 6.0 || bearing > kPi / 3.0 || std::fabs(dy - optimum) > 0.1 * optimum)
      continue;
    ++out.in_v;
    const double lag = lead->phase - b.phase;
    const double spatial = 2.0 * kPi * lead->frequency * dx / speed;
    out.in_phase += std::fabs(std::remainder(lag - spatial, 2.0 * kPi)) <= kPi / 4.0;
  }
  return out;
}

FormationFigures measure_formation(const Scenario& scenario, const std::vector<BirdState>& birds,
                                   uint32_t flock, double optimum) {
  std::vector<BirdState> members;
  for (const BirdState& b : birds)
    if (b.flock == flock && flocks_now(b) && is_finite(b)) members.push_back(b);
  return formation_figures(members, scenario.species[scenario.flocks[flock].species], optimum);
}

void FormationMean::add(const FormationFigures& f) {
  ++samples;
  sum.followers += f.followers;
  sum.in_v += f.in_v;
  sum.in_phase += f.in_phase;
}

double FormationMean::followers() const {
  return samples ? double(sum.followers) / double(samples) : 0.0;
}
double FormationMean::in_v() const {
  return sum.followers ? double(sum.in_v) / double(sum.followers)
                       : std::numeric_limits<double>::quiet_NaN();
}
double FormationMean::in_phase() const {
  return sum.in_v ? double(sum.in_phase) / double(sum.in_v)
                  : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace aeroflock
