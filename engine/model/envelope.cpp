#include "envelope.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <glm/gtc/quaternion.hpp>

#include "body.h"
#include "constants.h"
#include "flock_geometry.h"
#include "step.h"

namespace aeroflock {
namespace {

using glm::dvec3;

// cm: flights start 200 m up, 50 m above the lowest target; landings 2 m above a branch 5 m up
// (a species that does not perch lands on the ground under it).
constexpr double kStartHeight = 20000.0;
constexpr double kBranchHeight = 500.0;
constexpr double kTargetRadius = 300.0;  // cm
constexpr double kCruise = 1000.0;       // cm/s: the time limits allow 1.5 times the path at it
constexpr double kJudgeEvery = 0.006;    // s: the flights are judged every 6 ms (or every step)

double time_limit(const EnvelopeCase& c) {
  if (c.kind == EnvelopeCase::Kind::landing) return 60.0;
  return 20.0 + 1.5 * std::hypot(c.distance, c.rise) / kCruise;
}

// Where the case's target (branch) is, from a bird starting at the origin heading +x.
dvec3 goal(const EnvelopeCase& c, double start_height) {
  return {c.distance * std::cos(c.bearing), start_height + c.rise,
          c.distance * std::sin(c.bearing)};
}

}  // namespace

const char* name(Outcome o) {
  switch (o) {
    case Outcome::reached:
      return "reached";
    case Outcome::late:
      return "late";
    case Outcome::over_bank:
      return "over_bank";
    case Outcome::over_pitch:
      return "over_pitch";
    case Outcome::below_ground:
      return "below_ground";
    case Outcome::not_finite:
      return "not_finite";
  }
  return "?";
}

std::string EnvelopeCase::describe() const {
  char text[200];
  const char* k = kind == Kind::flight ? "flight" : kind == Kind::takeoff ? "takeoff" : "landing";
  std::snprintf(
      text, sizeof text,
      "%s speed %.0f m/s pitch %.0f bank %.0f deg, target %+.0f m up %.0f deg off %.0f m away, "
      "crosswind %.0f m/s",
      k, speed / 100, degrees(pitch), degrees(bank), rise / 100, degrees(bearing), distance / 100,
      crosswind / 100);
  return text;
}

std::vector<EnvelopeCase> envelope_cases(bool quick) {
  using V = std::vector<double>;
  const V speeds = quick ? V{1000} : V{500, 1000, 1500, 2000};
  const V pitches = quick ? V{0, 30} : V{-30, 0, 30};
  const V banks = quick ? V{0, 60} : V{-60, 0, 60};
  const V rises = quick ? V{2000, -5000} : V{5000, 2000, 0, -5000, -15000};
  const V bearings = quick ? V{0, 180} : V{0, 90, 180};
  const V distances = quick ? V{5000} : V{5000, 30000, 200000};
  const V winds = {0, 500, 800};
  std::vector<EnvelopeCase> cases;
  size_t n = 0;
  for (double speed : speeds)
    for (double pitch : pitches)
      for (double bank : banks)
        for (double rise : rises)
          for (double bearing : bearings)
            for (double distance : distances) {
              EnvelopeCase c;
              c.speed = speed;
              c.pitch = radians(pitch);
              c.bank = radians(bank);
              c.rise = rise;
              c.bearing = radians(bearing);
              c.distance = distance;
              c.crosswind = winds[n++ % winds.size()];
              cases.push_back(c);
            }
  // Take-offs: to a target 10 or 20 m up, 50 or 300 m ahead or off to the side.
  for (double wind : quick ? V{500} : winds)
    for (double rise : quick ? V{1000} : V{1000, 2000})
      for (double distance : quick ? V{5000} : V{5000, 30000})
        for (double bearing : quick ? V{0} : V{0, 90}) {
          EnvelopeCase c;
          c.kind = EnvelopeCase::Kind::takeoff;
          c.speed = 0.0;
          c.rise = rise;
          c.distance = distance;
          c.bearing = radians(bearing);
          c.crosswind = wind;
          cases.push_back(c);
        }
  // Branch landings: the branch 30 or 60 m away in eight directions, the bird 2 m above it.
  for (double wind : quick ? V{0} : winds)
    for (double distance : quick ? V{3000} : V{3000, 6000})
      for (int k = 0; k < 8; k += quick ? 2 : 1) {
        EnvelopeCase c;
        c.kind = EnvelopeCase::Kind::landing;
        c.rise = -200.0;
        c.distance = distance;
        c.bearing = radians(45.0 * k - (k >= 4 ? 360.0 : 0.0));
        c.crosswind = wind;
        cases.push_back(c);
      }
  return cases;
}

std::vector<EnvelopeCase> envelope_sample(size_t every, double farthest) {
  std::vector<EnvelopeCase> cases;
  size_t flights = 0;
  for (const EnvelopeCase& c : envelope_cases())
    if (c.kind != EnvelopeCase::Kind::flight || (c.distance <= farthest && flights++ % every == 0))
      cases.push_back(c);
  return cases;
}

FlightFaults flight_faults(const BirdState& b, const Species& species, double t,
                           double ground_height, bool flaring) {
  FlightFaults f;
  if (!is_finite(b)) {
    f.not_finite = true;
    return f;
  }
  f.below_ground = b.position.y < ground_height;
  if (t >= kSettleTime && b.mode != FlightMode::perched) {
    f.over_bank = std::fabs(bank_angle(b.attitude)) > species.bank_max + kBankMargin;
    f.over_pitch = std::fabs(pitch_angle(b.attitude)) >
                   (flaring || b.mode == FlightMode::landing ? kFlarePitchLimit : kPitchLimit);
  }
  return f;
}

EnvelopeFlight envelope_flight(const Species& species, const std::vector<EnvelopeCase>& cases,
                               double dt) {
  EnvelopeFlight flight;
  Scenario& s = flight.scenario;
  s.name = "envelope";
  s.species = {species};
  s.dt = dt;
  s.steps_per_frame = steps_in(kJudgeEvery, dt);
  s.world.wind =
      dvec3{0.0, 0.0,
            cases.empty() ? 0.0 : cases.front().crosswind};  // from the left of a bird heading +x
  for (size_t i = 0; i < cases.size(); ++i) {
    const EnvelopeCase& c = cases[i];
    BirdState b;
    b.route = static_cast<uint32_t>(s.world.routes.size());
    b.frequency = 0.5 * (species.f_min + species.f_max);
    b.amplitude = 0.5 * (species.amp_min + species.amp_max);
    Route r;
    r.name = "case" + std::to_string(i);
    if (c.kind == EnvelopeCase::Kind::landing) {
      const double start = kBranchHeight - c.rise;
      const double site = species.perches != 0.0 ? kBranchHeight : s.world.ground_height;
      Branch br;
      br.name = r.name;
      br.point = goal(c, start);
      br.point.y = site;
      // A site on the ground has no branch to come in across: it lies across the line from the
      // start, so that the bird comes straight in.
      if (species.perches == 0.0)
        br.direction = dvec3{-std::sin(c.bearing), 0.0, std::cos(c.bearing)};
      r.branch = static_cast<int32_t>(s.world.branches.size());
      s.world.branches.push_back(br);
      b.position = dvec3{0.0, start, 0.0};
    } else {
      const double start =
          c.kind == EnvelopeCase::Kind::takeoff ? species.stand_height : kStartHeight;
      Target t;
      t.name = r.name;
      t.centre = goal(c, start);
      t.radius = kTargetRadius;
      r.targets = {static_cast<uint32_t>(s.world.targets.size())};
      s.world.targets.push_back(t);
      b.position = dvec3{0.0, start, 0.0};
    }
    s.world.routes.push_back(r);
    if (c.kind == EnvelopeCase::Kind::takeoff) {
      b.mode = FlightMode::standing;
      b.attitude = heading_attitude(0.0);
      face_the_wind(b, species, s.world, kPi);
    } else {
      b.attitude = glm::angleAxis(c.pitch, dvec3{0, 0, 1}) * glm::angleAxis(c.bank, dvec3{1, 0, 0});
      // A landing begins in flight: no slower than the species flies (the migrants' min_speed is
      // above the case's 10 m/s: released slower, they stalled onto the ground at once).
      const double speed =
          c.kind == EnvelopeCase::Kind::landing ? std::max(c.speed, species.min_speed) : c.speed;
      b.velocity = b.attitude * dvec3{speed, 0.0, 0.0};
    }
    flight.birds.push_back(b);
    flight.longest = std::max(flight.longest, time_limit(c));
  }
  s.duration = flight.longest;
  validate(s);
  flight.frames = s.frames_reaching(flight.longest);
  return flight;
}

bool judge_envelope(EnvelopeResult& r, const BirdState& b, const Species& species, double t,
                    double ground_height) {
  auto verdict = [&](Outcome o) {
    r.outcome = o;
    r.time = t;
    return true;
  };
  if (b.mode == FlightMode::landing) r.flaring_until = t + kGoRoundGrace;
  const FlightFaults faults = flight_faults(b, species, t, ground_height, t <= r.flaring_until);
  if (faults.not_finite) return verdict(Outcome::not_finite);
  r.lowest = std::min(r.lowest, b.position.y - ground_height);
  if (faults.below_ground) return verdict(Outcome::below_ground);
  if (t >= kSettleTime && b.mode != FlightMode::perched) {
    r.worst_bank = std::max(r.worst_bank, std::fabs(bank_angle(b.attitude)));
    r.worst_pitch = std::max(r.worst_pitch, std::fabs(pitch_angle(b.attitude)));
  }
  if (faults.over_bank) return verdict(Outcome::over_bank);
  if (faults.over_pitch) return verdict(Outcome::over_pitch);
  const bool there = r.c.kind == EnvelopeCase::Kind::landing ? b.mode == FlightMode::perched
                                                             : b.targets_reached >= 1;
  if (there) return verdict(Outcome::reached);
  if (t >= time_limit(r.c)) return verdict(Outcome::late);
  return false;
}

}  // namespace aeroflock
