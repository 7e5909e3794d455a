#include "scenario.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace aeroflock {

double dt_of(Fidelity f) { return f == Fidelity::fast ? kFastDt : kPaperDt; }

const char* fidelity_name(double dt) {
  return dt == kPaperDt ? "paper" : dt == kFastDt ? "fast" : "custom";
}

Fidelity parse_fidelity(const std::string& name) {
  if (name == "paper") return Fidelity::paper;
  if (name == "fast") return Fidelity::fast;
  throw std::invalid_argument("expected \"paper\" or \"fast\", got \"" + name + "\"");
}

uint32_t steps_in(double seconds, double dt) {
  return static_cast<uint32_t>(std::max(1.0, std::round(seconds / dt)));
}

void set_dt(Scenario& s, double dt) {
  s.steps_per_frame = steps_in(s.frame_seconds(), dt);
  s.dt = dt;
}

void validate(const Scenario& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!(s.dt > 0.0) || !std::isfinite(s.dt)) fail("dt must be > 0");
  if (s.steps_per_frame < 1) fail("steps_per_frame must be >= 1");
  if (!(s.duration > 0.0) || !std::isfinite(s.duration)) fail("duration must be > 0");
  if (s.species.empty()) fail("no species");
  for (const Species& sp : s.species) validate(sp);
  const World& w = s.world;
  if (!(w.wind_height > 0.0) || !std::isfinite(w.wind_height)) fail("wind_height must be > 0");
  if (!(w.wind_exponent >= 0.0 && w.wind_exponent <= 1.0)) fail("wind_exponent must be within [0, 1]");
  if (!(w.wind_roughness > 0.0 && w.wind_roughness < w.wind_height))
    fail("wind_roughness must be > 0 and below wind_height");
  // The world the device keeps exact (gpu/host_device.h: world tiles).
  auto within_world = [&](const glm::dvec3& p, const std::string& what) {
    if (!(std::fabs(p.x) <= kWorldRadius && std::fabs(p.z) <= kWorldRadius))
      fail(what + " lies farther than 20,000 km from the origin");
  };
  for (const Target& t : w.targets) {
    if (!(t.radius > 0.0)) fail("target '" + t.name + "': radius must be > 0");
    within_world(t.centre, "target '" + t.name + "'");
  }
  for (const Branch& b : w.branches) within_world(b.point, "branch '" + b.name + "'");
  for (const Flock& f : s.flocks) within_world(f.spawn_centre, "flock '" + f.name + "'");
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

Scenario moved_by(Scenario s, const glm::dvec3& offset) {
  for (Target& t : s.world.targets) t.centre += offset;
  for (glm::dvec3& p : s.world.target_now) p += offset;
  for (Branch& b : s.world.branches) b.point += offset;
  for (Flock& f : s.flocks) f.spawn_centre += offset;
  s.world.ground_height += offset.y;
  return s;
}

void make_flock_non_finite(Scenario& s, const std::string& name) {
  for (Flock& f : s.flocks) {
    if (f.name != name) continue;
    Species doomed = s.species.at(f.species);
    doomed.name += " (NaN ground effect)";
    doomed.ground_k = std::numeric_limits<double>::quiet_NaN();
    f.species = static_cast<uint32_t>(s.species.size());
    s.species.push_back(doomed);
    return;
  }
  throw std::invalid_argument("make_flock_non_finite: no flock " + name);
}

void resize_flock(Scenario& s, size_t index, uint32_t count) {
  Flock& f = s.flocks.at(index);
  if (count == 0) {
    s.flocks.erase(s.flocks.begin() + static_cast<std::ptrdiff_t>(index));
    return;
  }
  f.spawn_extent *= std::cbrt(static_cast<double>(count) / static_cast<double>(f.count));
  f.count = count;
}

bool any_flocking(const Scenario& s) {
  for (const Flock& f : s.flocks)
    if (f.flocking) return true;
  return false;
}

}  // namespace aeroflock
