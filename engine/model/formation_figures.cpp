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
                                   double optimum, std::vector<FormationRole>* roles,
                                   const World* world) {
  FormationFigures out;
  if (roles) roles->assign(birds.size(), FormationRole::head);
  auto role = [&](size_t i, FormationRole r) {
    if (roles) (*roles)[i] = r;
  };
  auto air_velocity = [&](const BirdState& b) {
    return world ? b.velocity - wind_at(*world, b.position.y) : b.velocity;
  };
  for (size_t i = 0; i < birds.size(); ++i) {
    const BirdState& b = birds[i];
    const dvec3 air = air_velocity(b);
    const double own = glm::length(air);
    if (!(own > 0.0)) continue;
    const dvec3 ahead_b = air / own;
    const BirdState* lead = nullptr;
    double nearest = kWakeReach * s.box_c;
    for (size_t j = 0; j < birds.size(); ++j) {
      const dvec3 offset = birds[j].position - b.position;
      const double d = glm::length(offset);
      if (j != i && glm::dot(offset, ahead_b) >= kFormationBehind * s.box_c && d <= nearest)
        nearest = d, lead = &birds[j];
    }
    if (!lead) continue;
    const dvec3 lead_air = air_velocity(*lead);
    const double speed = glm::length(lead_air);
    const dvec3 across = glm::cross(lead_air, dvec3{0.0, 1.0, 0.0});
    if (!(speed > 0.0) || !(glm::length(across) > 0.0)) continue;
    ++out.followers;
    role(i, FormationRole::follower);
    const dvec3 ahead = lead_air / speed;
    const dvec3 side = glm::normalize(across);
    const dvec3 offset = b.position - lead->position;
    const double dx = -glm::dot(offset, ahead), dy = std::fabs(glm::dot(offset, side));
    // The phase lag less the wingtip path's.
    const double off_path =
        std::remainder(lead->phase - b.phase - 2.0 * kPi * lead->frequency * dx / speed, 2.0 * kPi);
    if (dy < kDirectlyBehind * s.box_c) {
      ++out.behind;
      out.anti_phase += std::fabs(off_path) >= 0.75 * kPi;
    }
    const double bearing = std::atan2(dx, dy);
    if (bearing < kPi / 6.0 || bearing > kPi / 3.0 || std::fabs(dy - optimum) > 0.1 * optimum)
      continue;
    ++out.in_v;
    role(i, FormationRole::in_v);
    out.in_phase += std::fabs(off_path) <= kPi / 4.0;
  }
  return out;
}

FormationFigures measure_formation(const Scenario& scenario, const std::vector<BirdState>& birds,
                                   uint32_t flock, double optimum,
                                   std::vector<FormationRole>* roles) {
  std::vector<BirdState> members;
  std::vector<size_t> index;
  for (size_t i = 0; i < birds.size(); ++i)
    if (birds[i].flock == flock && flocks_now(birds[i]) && is_finite(birds[i]))
      members.push_back(birds[i]), index.push_back(i);
  std::vector<FormationRole> member_roles;
  const FormationFigures f =
      formation_figures(members, scenario.species[scenario.flocks[flock].species], optimum,
                        roles ? &member_roles : nullptr, &scenario.world);
  if (roles) {
    roles->assign(birds.size(), FormationRole::none);
    for (size_t k = 0; k < index.size(); ++k) (*roles)[index[k]] = member_roles[k];
  }
  return f;
}

void FormationMean::add(const FormationFigures& f) {
  ++samples;
  sum.followers += f.followers;
  sum.in_v += f.in_v;
  sum.in_phase += f.in_phase;
  sum.behind += f.behind;
  sum.anti_phase += f.anti_phase;
}

void FormationMean::add_power(std::span<const FormationRole> roles,
                              std::span<const StepForces> forces) {
  for (size_t i = 0; i < std::min(roles.size(), forces.size()); ++i) {
    const double w = forces[i].power;
    switch (roles[i]) {
      case FormationRole::none:
        break;
      case FormationRole::head:
        power_sum[0] += w, ++power_frames[0];
        break;
      case FormationRole::in_v:
        power_sum[2] += w, ++power_frames[2];
        [[fallthrough]];
      case FormationRole::follower:
        power_sum[1] += w, ++power_frames[1];
        break;
    }
  }
}

double FormationMean::power_w(int k) const {
  return power_frames[k] ? 1e-7 * power_sum[k] / double(power_frames[k])
                         : std::numeric_limits<double>::quiet_NaN();
}

namespace {
double share(size_t part, size_t whole) {
  return whole ? double(part) / double(whole) : std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

double FormationMean::followers() const {
  return samples ? double(sum.followers) / double(samples) : 0.0;
}
double FormationMean::in_v() const { return share(sum.in_v, sum.followers); }
double FormationMean::in_phase() const { return share(sum.in_phase, sum.in_v); }
double FormationMean::behind() const { return share(sum.behind, sum.followers); }
double FormationMean::anti_phase() const { return share(sum.anti_phase, sum.behind); }

}  // namespace aeroflock
