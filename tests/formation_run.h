// Formation flying (issue 43, docs/MODEL.md "Formation flying"): a formation species, the place
// where its wing meets the most upwash behind another, and the figures of Portugal et al. 2014
// measured on a flock (tests/test_formation.cpp, tests/test_flock_vulkan.cpp).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "io/scenario_file.h"
#include "model/constants.h"
#include "model/flock.h"
#include "model/simulation.h"

namespace aeroflock::testing {

// `count` eagles that fly in formation (w_formation), released as a loose group 60 m across on a
// straight 3 km leg, their wakes on (`wake`). Separation 1.2 spans: a follower keeps that from
// the bird it follows.
inline Scenario formation_scenario(uint32_t count, bool wake, uint32_t seed = 3) {
  const std::string text = R"([simulation]
fidelity = "fast"
duration = 300.0
seed = )" + std::to_string(seed) +
                           R"(
[[species]]
name = "formation-eagle"
base = "eagle"
w_formation = 8.0
separation_radius = 264.0
w_separation = 2.0
[[targets]]
name = "end"
centre = [300000.0, 6000.0, 0.0]
radius = 3000.0
[[routes]]
name = "leg"
targets = ["end"]
[[flocks]]
species = "formation-eagle"
route = "leg"
count = )" + std::to_string(count) +
                           R"(
centre = [0.0, 6000.0, 0.0]
extent = [3000.0, 100.0, 3000.0]
flocking = true
wake = )" + (wake ? "true" : "false") +
                           "\n";
  return parse_scenario(text, "formation.toml");
}

// Where a follower `behind` (cm) another of its species, level at its height, meets the most
// upwash over its wingbeat (upwash_met, its wingbeat in the best phase): the lateral offset of
// centres, cm, to 0.005 spans. The optimum the model's own vortex spacing predicts.
inline double best_lateral_offset(const Species& s, double behind) {
  BirdState b;
  b.frequency = 0.5 * (s.f_min + s.f_max);
  b.amplitude = 0.8;
  b.velocity = glm::dvec3{1000.0, 0.0, 0.0};
  Perception p;
  p.wakes = 1;
  WakeSource& w = p.wake[0];
  w.air_velocity = b.velocity;
  w.lift = s.mass * kGravity;
  w.frequency = b.frequency;
  w.amplitude = b.amplitude;
  double best = -1e30, at = 0.0;
  for (int k = 0; k <= 300; ++k) {
    const double lateral = 0.005 * k * s.box_c;
    b.position = glm::dvec3{-behind, 0.0, lateral};
    double most = -1e30;  // over its phase
    for (int m = 0; m < 24; ++m)
      most = std::max(most, upwash_met(s, b, p, glm::dvec3{0.0, 1.0, 0.0}, glm::dvec3{0.0},
                                       2.0 * kPi * m / 24.0));
    if (most > best) best = most, at = lateral;
  }
  return at;
}

// The formation figures of one state: each follower (a bird with another at least
// kFormationBehind spans ahead of it along its flight, within kWakeReach spans: the nearest is
// the bird it follows) in the frame of the bird it follows.
struct FormationSample {
  size_t followers = 0;
  size_t in_v = 0;      // bearing 30-60 degrees behind the wing, lateral within 10 % of `optimum`
  size_t in_phase = 0;  // of those in V: phase lag within pi / 4 of 2 pi f dx / U
};
inline FormationSample formation_sample(const std::vector<BirdState>& birds, const Species& s,
                                        double optimum) {
  FormationSample out;
  for (size_t i = 0; i < birds.size(); ++i) {
    const BirdState& b = birds[i];
    const glm::dvec3 ahead_b = glm::normalize(b.velocity);
    const BirdState* lead = nullptr;
    double nearest = kWakeReach * s.box_c;
    for (size_t j = 0; j < birds.size(); ++j) {
      const glm::dvec3 offset = birds[j].position - b.position;
      const double d = glm::length(offset);
      if (j != i && glm::dot(offset, ahead_b) >= kFormationBehind * s.box_c && d <= nearest)
        nearest = d, lead = &birds[j];
    }
    if (!lead) continue;
    ++out.followers;
    const double speed = glm::length(lead->velocity);
    const glm::dvec3 ahead = lead->velocity / speed;
    const glm::dvec3 side = glm::normalize(glm::cross(ahead, glm::dvec3{0.0, 1.0, 0.0}));
    const glm::dvec3 offset = b.position - lead->position;
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

}  // namespace aeroflock::testing
