#include "route.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "body.h"
#include "constants.h"
#include "control.h"

namespace aeroflock {
namespace {

using glm::dvec3;

const Branch* route_branch(const BirdState& b, const World& w) {
  const Route& r = w.routes[b.route];
  if (r.branch < 0 || b.target < r.targets.size()) return nullptr;
  return &w.branches[static_cast<uint32_t>(r.branch)];
}

// Whether a bird lands into the wind: it does where the wind along the branch's horizontal
// perpendicular `across` is one it heeds.
bool into_wind(const Species& s, const dvec3& across, const dvec3& wind) {
  return heeds_wind(s, std::fabs(glm::dot(wind, across)));
}

// A point on the branch's horizontal perpendicular, on the side it is landed from, five approach
// distances out (kGateApproaches): where a bird that cannot turn onto the landing curve goes first.
dvec3 landing_gate(const Species& s, const dvec3& across, const dvec3& q2, double side) {
  return q2 + across * (side * kGateApproaches * s.approach_distance);
}

// Flown past the branch: moving away from it horizontally, out of perch_radius (a braking bird
// may sink a little, and one nearly still over the branch in a wind drift to and fro).
bool flown_past(const BirdState& b, const Species& s, const dvec3& to_perch) {
  return glm::dot(horizontal(to_perch), horizontal(b.velocity)) <= 0.0 &&
         glm::length(horizontal(to_perch)) > s.perch_radius;
}

// Sunk under the perch and still sinking fast: braking, it could not climb back onto it.
bool sunk_under(const BirdState& b, const Species& s, const dvec3& to_perch) {
  return to_perch.y > kSunkPerchRadii * s.perch_radius &&
         b.velocity.y < -kSunkTouchdowns * s.touchdown_speed;
}

// Landing with path control (paper 4.4): P and the curve Q1 Q3 Q2 are placed when the branch
// becomes the goal, and the bird steers approach_distance ahead along the curve, which ends
// perpendicular to the branch. Where the bird's heading line does not cross the branch's
// perpendicular ahead (after a missed landing, say), or is not well out on the side it lands from,
// it first flies to a gate on that perpendicular, then lands from there.
dvec3 landing_goal(BirdState& b, const Species& s, const Branch& br, const dvec3& wind) {
  const dvec3 q2 = perch_point(s, br);
  const dvec3 across{-br.direction.z, 0.0, br.direction.x};
  // The side (+1 or -1 along `across`) it lands from: the downwind one, else where it is.
  const bool windward = into_wind(s, across, wind);
  const double side = glm::dot(windward ? wind : b.position - q2, across) < 0.0 ? -1.0 : 1.0;
  const dvec3 track = horizontal(b.velocity), inward = horizontal(q2 - b.position);
  auto place_curve = [&] {
    b.landing_start = b.position;
    b.via_point = landing_point(b.position, b.attitude * dvec3{1.0, 0.0, 0.0}, q2, br.direction);
    b.landing_progress = 0.0;
  };
  if (b.landing_stage == LandingStage::none) {
    place_curve();
    // No crossing ahead: lined up with the branch and heading in, or go round through the gate.
    const bool heading_in = glm::dot(track, inward) > 0.0;
    // Into the wind the bird must be well out on its side to come in along the perpendicular.
    const double out = windward ? s.approach_distance : 0.0;
    const bool on_side = glm::dot(b.position - q2, across) * side >= out;
    b.landing_stage =
        on_side && (b.via_point != q2 || heading_in) ? LandingStage::curve : LandingStage::gate;
  }
  if (b.landing_stage == LandingStage::gate) {
    // Reached within approach_distance, or flown past close by (as a target, route_goal), unless
    // heading away from the branch: that bird turns back to the gate first (a curve placed then
    // would lead it on out, 200 m downwind in an 8 m/s wind).
    const dvec3 gate = landing_gate(s, across, q2, side);
    const dvec3 to_gate = horizontal(gate - b.position);
    const double distance = glm::length(to_gate);
    const bool gone_by = glm::dot(to_gate, b.velocity) < 0.0;
    const bool heading_out =
        glm::dot(track, inward) < -kGateHeadingOut * glm::length(track) * glm::length(inward);
    if (heading_out || (distance > s.approach_distance &&
                        !(gone_by && distance <= kMissedTargetRadii * s.approach_distance)))
      return gate;
    place_curve();
    b.landing_stage = LandingStage::curve;
  }
  if (b.landing_progress >= 1.0 || b.via_point == q2) {
    // At the end of the curve (or lined up): straight in, unless the bird has flown past the
    // branch, which it would only circle: then round through the gate again.
    if (flown_past(b, s, q2 - b.position)) b.landing_stage = LandingStage::gate;
    return q2;
  }
  b.landing_progress = landing_progress(b.landing_start, b.via_point, q2, b.landing_progress,
                                        b.position, s.approach_distance);
  // Along the curve at the perch's height: a bird that placed it from low down climbs back first.
  dvec3 on_curve = landing_curve(b.landing_start, b.via_point, q2, b.landing_progress);
  on_curve.y = q2.y;
  return on_curve;
}

// A bird that lands on the ground (route.h: lands_on_ground) steers for `goal` (landing_goal's)
// at the height of its glide path: on the way to the gate, the path's height there (it climbs to
// where its final begins); on its final, the path's height where it will be a height_lead on, so
// that its height error (control.h: steer_towards leads it by as much) is how far it is off the
// path where it is. The path runs on under the ground past the site, so that the bird sinks at
// the path's rate until its legs meet the ground (ending it level at the site, the lead would
// float it on over the ground). Past the site it flies straight on.
dvec3 glide_goal(const BirdState& b, const Species& s, const Branch& br, dvec3 goal,
                 const dvec3& wind) {
  const dvec3 site = perch_point(s, br);
  const double slope = std::tan(kGlideSlope);
  if (b.landing_stage == LandingStage::gate) {
    goal.y = site.y + slope * glm::length(horizontal(goal - site));
    return goal;
  }
  const dvec3 ground_velocity = horizontal(b.velocity);
  const double speed = glm::length(ground_velocity);
  if (!(speed > 0.0)) return goal;
  // How far it has to go to the site: along its track near it (negative once past it), else the
  // whole way (turning onto its final, it may head away from the site).
  const dvec3 way = horizontal(site - b.position);
  const double along = glm::dot(way, ground_velocity) / speed;
  const bool near = glm::length(way) <= s.perch_radius;
  const double ahead = near ? along : glm::length(way);
  if (near && along <= 0.0) {
    const dvec3 air = horizontal(b.velocity - wind);
    goal =
        b.position + (glm::length(air) > 0.0 ? air / glm::length(air) : ground_velocity / speed) *
                         s.approach_distance;
  }
  goal.y = site.y + slope * (ahead - s.height_lead * speed);
  return goal;
}

void perch(BirdState& b, const Species& s, const Branch& br) {
  hold_on(b, FlightMode::perched, perch_point(s, br));
  ++b.targets_reached;
}

}  // namespace

dvec3 perch_point(const Species& s, const Branch& branch) {
  return branch.point + dvec3{0.0, s.stand_height, 0.0};
}

bool route_over(const BirdState& b, const World& w) {
  const Route& r = w.routes[b.route];
  return b.target >= r.targets.size() && r.branch < 0;
}

std::optional<dvec3> onward_goal(const BirdState& b, const World& w) {
  const Route& r = w.routes[b.route];
  if (!route_over(b, w) || r.targets.size() < 2) return std::nullopt;
  const dvec3& last = w.target_now[r.targets.back()];
  const dvec3& before = w.target_now[r.targets[r.targets.size() - 2]];
  dvec3 goal = b.position + horizontal(last - before);
  goal.y = last.y;
  return goal;
}

std::optional<double> distance_to_go(const BirdState& b, const World& w) {
  const Route& r = w.routes[b.route];
  if (r.loop && r.branch < 0) return std::nullopt;
  if (b.mode == FlightMode::perched) return 0.0;
  double to_go = 0.0;
  dvec3 from = b.position;
  for (size_t k = b.target; k < r.targets.size(); ++k) {
    const dvec3& next = w.target_now[r.targets[k]];
    to_go += glm::length(next - from);
    from = next;
  }
  if (r.branch >= 0) to_go += glm::length(w.branches[size_t(r.branch)].point - from);
  return to_go;
}

// Entering a target's sphere passes it (paper 3.4); so does flying past it close by, so that a
// sphere missed by a little does not trap the bird in an orbit around it. After the last target
// of a route that neither loops nor lands, the bird keeps steering for that target.
dvec3 route_goal(BirdState& b, const Species& s, const World& w) {
  const Route& r = w.routes[b.route];
  const uint32_t n = static_cast<uint32_t>(r.targets.size());
  if (b.target < n) {
    const Target& t = w.targets[r.targets[b.target]];
    const dvec3 to_target = w.target_now[r.targets[b.target]] - b.position;
    const double distance = glm::length(to_target);
    const bool gone_by = glm::dot(to_target, b.velocity - t.velocity) < 0.0;
    if (distance <= t.radius || (distance <= kMissedTargetRadii * t.radius && gone_by)) {
      ++b.targets_reached;
      ++b.target;
      if (b.target == n && r.loop && r.branch < 0) b.target = 0;
    }
  }
  if (b.target < n) return w.target_now[r.targets[b.target]];
  if (r.branch < 0) return w.target_now[r.targets[n - 1]];
  const Branch& br = w.branches[static_cast<uint32_t>(r.branch)];
  const dvec3 wind = wind_at(w, b.position.y);
  const dvec3 goal =
      r.path_control ? landing_goal(b, s, br, wind) : perch_point(s, br);  // or straight in
  return lands_on_ground(s) ? glide_goal(b, s, br, goal, wind) : goal;
}

bool lands_on_ground(const Species& s) { return s.perches == 0.0; }

bool at_landing_site(const BirdState& b, const Species& s, const World& w, const dvec3& at) {
  const Branch* br = route_branch(b, w);
  return br && lands_on_ground(s) && glm::length(horizontal(at - br->point)) <= s.perch_radius;
}

std::optional<dvec3> way_to_perch(const BirdState& b, const Species& s, const World& w) {
  const Branch* br = route_branch(b, w);
  if (!br || b.landing_stage == LandingStage::gate) return std::nullopt;
  return perch_point(s, *br) - b.position;
}

double last_beat_speed(const BirdState& b) {
  if (!(b.frequency > 0.0)) return glm::length(b.velocity);
  const double period = 1.0 / b.frequency;
  const double window = std::max(period, kTouchdownWindow);
  const double into = std::min(b.phase / (2.0 * kPi) * period, period);
  return (b.beat_path + b.beat_speed * (window - into)) / window;
}

namespace {
// Whether the flare needs starting now to touch down at perch_radius (the wind where the bird is).
bool braking_due(const Species& s, const BirdState& b, const dvec3& to_perch, const dvec3& wind,
                 double distance) {
  return flare_share(s, glm::length(b.velocity - wind), perch_airspeed(s, to_perch, wind),
                     distance) >= kBrakeShare;
}
}  // namespace

bool approach_branch(BirdState& b, const Species& s, const World& w) {
  const Branch* br = route_branch(b, w);
  // A bird that lands on the ground does not brake: it touches down at its slowest airspeed.
  if (!br || lands_on_ground(s)) return false;
  const dvec3 to_perch = perch_point(s, *br) - b.position;
  const double distance = glm::length(to_perch);
  // Hovering onto it, it grips where its feet meet the branch point, slowly over its last
  // wingbeat; flaring, anywhere within perch_radius once it is slow.
  const bool grips =
      hovers(s) ? distance <= kGripReach * s.stand_height && last_beat_speed(b) <= s.touchdown_speed
                : distance <= s.perch_radius && glm::length(b.velocity) <= s.touchdown_speed;
  if (grips) {
    perch(b, s, *br);
    return true;
  }
  // Overshot (flown past; landing_goal has sent it round through the gate on the same test) or
  // sunk under the branch: go round and plan the landing again.
  const bool closing = glm::dot(horizontal(to_perch), horizontal(b.velocity)) > 0.0;
  if (b.mode == FlightMode::landing && (flown_past(b, s, to_perch) || sunk_under(b, s, to_perch))) {
    b.mode = FlightMode::flying;
    b.mode_steps = 0;
    b.landing_stage = LandingStage::none;
  } else if (b.mode == FlightMode::flying && closing && b.landing_stage != LandingStage::gate &&
             (distance <= (hovers(s) ? kHoverBrakeDistances : 1.0) * s.brake_distance ||
              braking_due(s, b, to_perch, wind_at(w, b.position.y), distance))) {
    b.mode = FlightMode::landing;
    b.mode_steps = 0;
  }
  return false;
}

}  // namespace aeroflock
