// Formation flying (issue 43, docs/MODEL.md "Formation flying"): a formation species' flock for
// the tests (tests/test_formation.cpp, tests/test_flock_vulkan.cpp); the place where its wing meets
// the most upwash and the figures of Portugal et al. 2014 are model/formation_figures.h's.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "io/scenario_file.h"
#include "model/formation_figures.h"
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

// How far a flock's mean height strays from its route's height `route` (cm) from `from` to
// `until` seconds, a frame at a time (the worst frame, and the mean), and whether every bird
// stayed finite.
struct HeightHeld {
  double worst = 0.0;  // cm
  double mean = 0.0;   // cm: its mean over those frames (above the route > 0)
  bool finite = true;
};
inline HeightHeld height_held(Simulation& sim, double route, double from, double until) {
  HeightHeld h;
  size_t frames = 0;
  while (sim.time() < until - 1e-9) {
    sim.step_frame();
    double mean = 0.0;
    for (const BirdState& b : sim.birds()) {
      h.finite = h.finite && all_finite(b);
      mean += b.position.y / double(sim.birds().size());
    }
    if (sim.time() >= from) {
      h.worst = std::max(h.worst, std::fabs(mean - route));
      h.mean += mean - route, ++frames;
    }
  }
  if (frames > 0) h.mean /= double(frames);
  return h;
}

}  // namespace aeroflock::testing
