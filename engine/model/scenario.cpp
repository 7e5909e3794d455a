#include "scenario.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "body.h"

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
  // Clamped before the cast: a double beyond uint32_t's range does not convert.
  return static_cast<uint32_t>(std::clamp(std::round(seconds / dt), 1.0, double(UINT32_MAX)));
}

namespace {
std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}
}  // namespace

void check_dt(double dt) {
  if (!(dt >= kMinDt && dt <= kMaxDt))
    throw std::invalid_argument("dt must be within [" + number(kMinDt) + ", " + number(kMaxDt) +
                                "] s (docs/convergence.md), got " + number(dt) + " s");
}

uint64_t Scenario::frames_reaching(double seconds) const {
  if (!(seconds > 0.0)) return 0;
  // From just below the estimate, then exactly as the time is counted (rounding decides the last).
  uint64_t frames = uint64_t(std::max(0.0, std::floor(seconds / frame_seconds()) - 1.0));
  while (double(frames * steps_per_frame) * dt < seconds) ++frames;
  return frames;
}

void check_takeoff_steps(const Scenario& s, double dt) {
  for (size_t i = 0; i < s.flocks.size(); ++i)
    if (s.flocks[i].standing && !takeoff_counts(s.flocks[i].takeoff_time, dt))
      throw std::invalid_argument("flocks[" + std::to_string(i) + "].takeoff_time of " +
                                  number(s.flocks[i].takeoff_time) +
                                  " s is more than 2^32 - 1 steps of " + number(dt) + " s");
}

void set_dt(Scenario& s, double dt) {
  check_dt(dt);
  check_takeoff_steps(s, dt);
  const double steps = std::round(s.frame_seconds() / dt);
  if (steps > kMaxStepsPerFrame)
    throw std::invalid_argument(
        "a frame of " + number(s.frame_seconds()) + " s takes " + number(steps) + " steps of " +
        number(dt) + " s; steps_per_frame must be <= " + std::to_string(kMaxStepsPerFrame));
  s.steps_per_frame = steps_in(s.frame_seconds(), dt);
  s.dt = dt;
}

void validate(const Scenario& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  check_dt(s.dt);
  if (s.steps_per_frame < 1 || s.steps_per_frame > kMaxStepsPerFrame)
    fail("steps_per_frame must be within [1, " + std::to_string(kMaxStepsPerFrame) + "]");
  if (!(s.duration > 0.0 && s.duration <= kMaxDuration))
    fail("duration must be within (0, " + number(kMaxDuration) + "] s");
  if (s.species.empty()) fail("no species");
  for (const Species& sp : s.species) validate(sp);
  check_takeoff_steps(s, s.dt);
  const World& w = s.world;
  if (!(w.wind_height > 0.0) || !std::isfinite(w.wind_height)) fail("wind_height must be > 0");
  if (!(w.wind_exponent >= 0.0 && w.wind_exponent <= 1.0))
    fail("wind_exponent must be within [0, 1]");
  if (!(w.wind_roughness > 0.0 && w.wind_roughness < w.wind_height))
    fail("wind_roughness must be > 0 and below wind_height");
  // The world the device keeps exact (gpu/host_device.h: world tiles).
  auto within_world = [&](const glm::dvec3& p, const std::string& what) {
    if (!(std::fabs(p.x) <= kWorldRadius && std::fabs(p.z) <= kWorldRadius))
      fail(what + " lies farther than 20,000 km from the origin");
  };
  // Nothing starts under the ground (the birds would stay down there); a target may lie on it.
  auto require_above_ground = [&](const glm::dvec3& p, const std::string& what, bool on = false) {
    if (!above_ground(p.y, w, on))
      fail(what + " is not above the ground (y " + number(p.y) + " cm, the ground " +
           number(w.ground_height) + " cm)");
  };
  for (const Target& t : w.targets) {
    if (!(t.radius > 0.0)) fail("target '" + t.name + "': radius must be > 0");
    within_world(t.centre, "target '" + t.name + "'");
    require_above_ground(t.centre, "target '" + t.name + "'",
                         true);  // Fig. 17's lies on the ground
  }
  for (const Branch& b : w.branches) {
    within_world(b.point, "branch '" + b.name + "'");
    require_above_ground(b.point, "branch '" + b.name + "'",
                         true);  // one on the ground is a landing site there
  }
  for (const Flock& f : s.flocks) {
    within_world(f.spawn_centre, "flock '" + f.name + "'");
    if (f.wake && !f.flocking)
      fail("flock '" + f.name + "': wake needs flocking (a bird meets the wakes of those it sees)");
  }
  for (const Route& r : w.routes) {
    if (r.targets.empty() && r.branch < 0) fail("route '" + r.name + "' has no targets");
    if (r.loop && r.targets.size() < 2)
      fail("route '" + r.name + "' loops over fewer than 2 targets");
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
    const Species& sp = s.species[f.species];
    // A standing flock stands its birds' centres stand_height above the ground, whatever its
    // box's height; a flying one starts anywhere in its box.
    if (f.standing && !(sp.stand_height > 0.0))
      fail("flock '" + f.name + "': its species '" + sp.name +
           "' stands at stand_height 0, on the ground");
    if (!f.standing)
      require_above_ground(
          f.spawn_centre - glm::dvec3{0.0, spawn_extent(f, sp, f.count, w.ground_height).y, 0.0},
          "flock '" + f.name + "': the lowest point of its spawn box");
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
  if (f.spawn_extent != glm::dvec3{0.0})
    f.spawn_extent = spawn_extent(f, s.species.at(f.species), count, s.world.ground_height);
  f.count = count;
}

glm::dvec3 spawn_extent(const Flock& f, const Species& sp, uint32_t count, double ground_height) {
  const bool own_box = f.spawn_extent != glm::dvec3{0.0};
  if (count == f.count && (own_box || count <= 1)) return f.spawn_extent;
  glm::dvec3 e =
      own_box ? f.spawn_extent * std::cbrt(static_cast<double>(std::max(count, 1u)) /
                                           static_cast<double>(f.count))
              : glm::dvec3{count > 1 ? 2.0 * sp.wing_length * std::cbrt(static_cast<double>(count))
                                     : 0.0};
  // A grown box keeps its lowest point above the ground (at most 90 % of the centre's height
  // over it) and widens instead, as dense as before.
  const double room = 0.9 * (f.spawn_centre.y - ground_height);
  if (count != f.count && e.y > room && room > 0.0) {
    const double widen = std::sqrt(e.y / room);
    e = {e.x * widen, room, e.z * widen};
  }
  return e;
}

bool any_flocking(const Scenario& s) {
  for (const Flock& f : s.flocks)
    if (f.flocking) return true;
  return false;
}

bool any_wake(const Scenario& s) {
  for (const Flock& f : s.flocks)
    if (f.flocking && f.wake) return true;
  return false;
}

std::vector<WindBeyondAirspeed> wind_beyond_airspeed(const Scenario& s) {
  std::vector<WindBeyondAirspeed> legs;
  for (size_t f = 0; f < s.flocks.size(); ++f) {
    const Flock& flock = s.flocks[f];
    if (flock.route >= s.world.routes.size()) continue;
    const Route& route = s.world.routes[flock.route];
    // A flock that flocks flies its birds' airspeed (cruise_speed to start with); a bird alone
    // flies faster against the wind, up to max_speed (control.h: commanded_airspeed).
    const Species& species = s.species[flock.species];
    const double airspeed = flock.flocking ? species.cruise_speed : species.max_speed;
    glm::dvec3 from = flock.spawn_centre;
    uint32_t from_target = WindBeyondAirspeed::kSpawn;
    const size_t legs_flown = route.targets.size() + (route.loop && route.targets.size() > 1);
    for (size_t k = 0; k < legs_flown; ++k) {
      const uint32_t to = route.targets[k % route.targets.size()];
      const glm::dvec3 end = s.world.targets[to].centre;
      const glm::dvec3 way = horizontal(end - from);
      if (glm::length(way) > 0.0) {
        const glm::dvec3 along = glm::normalize(way);
        WindBeyondAirspeed worst{uint32_t(f), from_target, to, 0.0, 0.0, 0.0, airspeed};
        // The speed made good along the leg with the track held, at each end: not above 0 where
        // it cannot be held (across at least the airspeed: below 0 whatever the wind along). The
        // end where it is least is reported.
        double least = std::numeric_limits<double>::infinity();
        for (const double y : {from.y, end.y}) {
          const glm::dvec3 w = horizontal(wind_at(s.world, y));
          const double across = glm::length(w - along * glm::dot(along, w));
          const double against = -glm::dot(along, w);
          const double made_good = across >= airspeed
                                       ? -across - airspeed
                                       : std::sqrt(airspeed * airspeed - across * across) - against;
          if (made_good < least)
            least = made_good, worst.across = across, worst.against = against, worst.height = y;
        }
        if (least <= 0.0) legs.push_back(worst);
      }
      from = end;
      from_target = to;
    }
  }
  return legs;
}

}  // namespace aeroflock
