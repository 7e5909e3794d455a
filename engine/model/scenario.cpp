#include "scenario.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace aeroflock {

void validate(const Scenario& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!(s.dt > 0.0) || !std::isfinite(s.dt)) fail("dt must be > 0");
  if (s.steps_per_frame < 1) fail("steps_per_frame must be >= 1");
  if (!(s.duration > 0.0) || !std::isfinite(s.duration)) fail("duration must be > 0");
  if (s.species.empty()) fail("no species");
  for (const Species& sp : s.species) validate(sp);
  const World& w = s.world;
  for (const Target& t : w.targets)
    if (!(t.radius > 0.0)) fail("target '" + t.name + "': radius must be > 0");
  for (const Route& r : w.routes) {
    if (r.targets.empty() && r.branch < 0) fail("route '" + r.name + "' has no targets");
    if (r.loop && r.targets.size() < 2) fail("route '" + r.name + "' loops over fewer than 2 targets");
    if (r.loop && r.branch >= 0) fail("route '" + r.name + "' both loops and lands on a branch");
    for (uint32_t t : r.targets)
      if (t >= w.targets.size()) fail("route '" + r.name + "': target index out of range");
    if (r.branch >= static_cast<int32_t>(w.branches.size()))
      fail("route '" + r.name + "': branch index out of range");
  }
  for (const Branch& b : w.branches)
    if (std::fabs(b.direction.y) > 1e-9 || std::fabs(glm::length(b.direction) - 1.0) > 1e-9)
      fail("branch '" + b.name + "': direction must be a horizontal unit vector");
  for (const Flock& f : s.flocks) {
    if (f.species >= s.species.size()) fail("flock '" + f.name + "': species out of range");
    if (f.route >= w.routes.size()) fail("flock '" + f.name + "': route out of range");
    if (f.count < 1) fail("flock '" + f.name + "': count must be >= 1");
  }
}

bool any_flocking(const Scenario& s) {
  for (const Flock& f : s.flocks)
    if (f.flocking) return true;
  return false;
}

}  // namespace aeroflock
