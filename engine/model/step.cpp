#include "step.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "aerodynamics.h"
#include "body.h"
#include "constants.h"
#include "control.h"
#include "tail.h"
#include "wingbeat.h"

namespace aeroflock {
namespace {

using glm::dquat;
using glm::dvec3;

const dvec3 kUp{0.0, 1.0, 0.0};
// A target flown past within this many radii counts as passed.
constexpr double kMissedTargetRadii = 3.0;

dvec3 horizontal(const dvec3& v) { return {v.x, 0.0, v.z}; }

// Where the bird sits when perched on a branch.
dvec3 perch_point(const Species& sp, const Branch& br) { return br.point + kUp * sp.stand_height; }

// A point on the branch's horizontal perpendicular, on the bird's side, three approach distances
// out: where a bird that cannot turn onto the landing curve goes first.
dvec3 landing_gate(const Species& sp, const Branch& br, const dvec3& q2, const dvec3& position) {
  const dvec3 across{-br.direction.z, 0.0, br.direction.x};
  const double side = glm::dot(position - q2, across) < 0.0 ? -1.0 : 1.0;
  return q2 + across * (side * 3.0 * sp.approach_distance);
}

// The bird's goal this step: the current target of its route, or the landing path to its branch.
// Entering a target's sphere passes it (paper 3.4). After the last target of a route that neither
// loops nor lands, the bird keeps steering for that target.
dvec3 route_goal(BirdState& b, const Species& sp, const World& w) {
  const Route& r = w.routes[b.route];
  const uint32_t n = static_cast<uint32_t>(r.targets.size());
  if (b.target < n) {
    const uint32_t ti = r.targets[b.target];
    const dvec3 to_target = w.target_now[ti] - b.position;
    const double distance = glm::length(to_target), radius = w.targets[ti].radius;
    // Entering the sphere passes the target; so does flying past it close by, so that a sphere
    // missed by a little does not trap the bird in an orbit around it.
    const bool passed = distance <= radius ||
                        (distance <= kMissedTargetRadii * radius && glm::dot(to_target, b.velocity) < 0.0);
    if (passed) {
      ++b.targets_reached;
      ++b.target;
      if (b.target == n && r.loop && r.branch < 0) b.target = 0;
    }
  }
  if (b.target < n) return w.target_now[r.targets[b.target]];
  if (r.branch < 0) return w.target_now[r.targets[n - 1]];

  // Landing (paper 4.4): P and the curve Q1 Q3 Q2 are placed when the branch becomes the goal,
  // and the bird steers approach_distance ahead along the curve, which ends perpendicular to the
  // branch. Where the bird's heading line does not cross the branch's perpendicular ahead (after a
  // missed landing, say), it first flies to a gate on that perpendicular, then lands from there.
  // The direct method flies straight at the branch.
  const Branch& br = w.branches[static_cast<uint32_t>(r.branch)];
  const dvec3 q2 = perch_point(sp, br);
  if (!r.path_control) return q2;
  auto place_curve = [&] {
    b.landing_start = b.position;
    b.via_point = landing_point(b.position, b.attitude * dvec3{1.0, 0.0, 0.0}, q2, br.direction);
    b.landing_progress = 0.0;
  };
  if (b.landing_stage == 0) {
    place_curve();
    b.landing_stage = b.via_point == q2 ? 1 : 2;
  }
  if (b.landing_stage == 1) {
    const dvec3 gate = landing_gate(sp, br, q2, b.position);
    if (glm::length(horizontal(gate - b.position)) > sp.approach_distance) return gate;
    place_curve();
    b.landing_stage = 2;
  }
  if (b.via_point == q2) return q2;  // on the perpendicular already: straight in
  b.landing_progress = landing_progress(b.landing_start, b.via_point, q2, b.landing_progress,
                                        b.position, sp.approach_distance);
  return landing_curve(b.landing_start, b.via_point, q2, b.landing_progress);
}

bool lands_on_branch(const BirdState& b, const World& w) {
  const Route& r = w.routes[b.route];
  return r.branch >= 0 && b.target >= r.targets.size();
}

void perch(BirdState& b, const Species& sp, const World& w) {
  const Branch& br = w.branches[static_cast<uint32_t>(w.routes[b.route].branch)];
  const dvec3 head = horizontal(b.attitude * dvec3{1.0, 0.0, 0.0});
  b.position = perch_point(sp, br);
  b.velocity = dvec3{0.0};
  b.omega = dvec3{0.0};
  b.attitude = heading_attitude(std::atan2(head.z, head.x));
  b.amplitude = 0.0;
  b.tail_bend = 0.0;
  b.tail_twist = 0.0;
  b.mode = FlightMode::perched;
  b.mode_time = 0.0;
  ++b.targets_reached;
}

}  // namespace

void step_bird(BirdState& b, const Species& sp, const World& w, double time, double dt,
               StepForces* out) {
  StepForces f{};
  if (b.mode == FlightMode::perched ||
      (b.mode == FlightMode::standing && time + 0.5 * dt < b.takeoff_time)) {
    b.mode_time += dt;
    if (out) *out = f;
    return;
  }
  if (b.mode == FlightMode::standing) {
    b.mode = FlightMode::taking_off;
    b.mode_time = 0.0;
    b.frequency = sp.f_max;
    b.amplitude = sp.amp_max;
  }
  const bool on_legs = b.mode == FlightMode::taking_off;
  const dvec3 head = b.attitude * dvec3{1.0, 0.0, 0.0};
  const double speed = glm::length(b.velocity);

  // --- Control (paper 3.4, 4.1, 4.4) from the state at time t.
  const dvec3 goal = route_goal(b, sp, w);
  const Steering steering = steer_towards(sp, b.attitude, b.position, b.velocity, goal);
  if (lands_on_branch(b, w)) {
    const double to_branch = glm::distance(b.position, perch_point(sp, w.branches[static_cast<uint32_t>(w.routes[b.route].branch)]));
    if (to_branch <= sp.perch_radius) {
      perch(b, sp, w);
      if (out) *out = f;
      return;
    }
    const dvec3 to_perch = perch_point(sp, w.branches[static_cast<uint32_t>(w.routes[b.route].branch)]) - b.position;
    if (b.mode == FlightMode::landing && glm::dot(to_perch, b.velocity) < 0.0) {
      b.mode = FlightMode::flying;  // overshot: go round and plan the landing again
      b.mode_time = 0.0;
      b.landing_stage = 0;
    } else if (b.mode == FlightMode::flying && to_branch <= sp.brake_distance) {
      b.mode = FlightMode::landing;
      b.mode_time = 0.0;
    }
  }
  const bool braking = b.mode == FlightMode::landing;
  // The tail twist steers the tail model; with fixed-rate turning it only shows the turn.
  const bool fixed_rate = w.turning == TurningModel::fixed_rate && !braking;
  TailCommand tail_cmd = tail_command(sp, steering, fixed_rate);
  // The tail twists towards the turn but never stands on edge: bank plus twist stay within
  // tail_roll_max, so that the tail still holds the body's pitch in a steep turn.
  const double twist_room = std::max(0.0, sp.tail_roll_max - std::fabs(bank_angle(b.attitude)));
  tail_cmd.twist = std::clamp(tail_cmd.twist, -twist_room, twist_room);
  double opening = tail_opening(sp, b.tail_bend, b.tail_twist);
  if (braking) opening = sp.Ct * std::max(sp.bend_max, sp.rot_max) + sp.tail_min;

  // Kinematic rotation rates (body frame) set by the controller: bank (both turning models),
  // yaw at the standard rate R (fixed-rate model, eq. 3), pitch-up to brake (landing).
  dvec3 omega = b.omega;
  if (on_legs) {
    omega = dvec3{0.0};
  } else {
    // Bank into the turn: in proportion to the heading error (tail model), or coordinated with
    // eq. 3's yaw rate -sgn(phi) R (fixed-rate model).
    const double turn_rate = sign_outside(steering.heading_error, sp.dead_band) * sp.turn_rate;
    const double to_goal = glm::length(horizontal(goal - b.position));
    double bank_cmd = pursuit_bank(sp, steering.heading_error, to_goal, speed);
    if (fixed_rate) bank_cmd = coordinated_bank(sp, turn_rate, speed);
    if (braking) bank_cmd = 0.0;
    omega.x = std::clamp((bank_cmd - bank_angle(b.attitude)) / sp.bank_time, -sp.roll_rate,
                         sp.roll_rate);
    if (fixed_rate) omega.y = -turn_rate;
    if (braking)
      omega.z = std::clamp((sp.brake_pitch - pitch_angle(b.attitude)) / sp.bank_time,
                           -sp.roll_rate, sp.roll_rate);
  }

  // --- Forces at time t.
  const glm::dmat3 to_world = glm::mat3_cast(b.attitude);
  const glm::dmat3 to_body = glm::transpose(to_world);
  const dvec3 body_velocity = to_body * b.velocity;
  const dvec3 body_wind = to_body * w.wind;
  auto air_at = [&](const dvec3& r, const dvec3& own) {
    return body_wind - (body_velocity + glm::cross(omega, r) + own);
  };

  dvec3 torque{0.0};  // eq. 11 summed over the five force points, body frame
  WingPoint right[2];
  right_wing_points(sp, b.phase, b.amplitude, b.frequency, right);
  for (int i = 0; i < 2; ++i) {
    const WingPoint left = mirror_to_left(right[i]);
    const WingPoint* points[2] = {&right[i], &left};
    for (int side = 0; side < 2; ++side) {
      const WingPoint& p = *points[side];
      const dvec3 force = aerodynamic_force(sp, air_at(p.position, p.velocity), p.chord, p.normal, p.area);
      f.wing[2 * side + i] = to_world * force;
      torque += glm::cross(p.position, force);
    }
  }
  const TailGeometry tg = tail_geometry(sp, b.tail_bend, b.tail_twist);
  const dvec3 tail_body = aerodynamic_force(sp, air_at(tg.position, dvec3{0.0}), tg.chord, tg.normal, tail_area(sp, opening));
  f.tail = to_world * tail_body;
  f.tail_torque = glm::cross(tg.position, tail_body);  // eq. 11
  f.torque = torque + f.tail_torque;
  f.gravity = dvec3{0.0, -sp.mass * kGravity, 0.0};
  const double height = b.position.y - w.ground_height;
  if (w.ground_effect) f.ground = kUp * ground_effect_force(sp, height);  // eq. 15
  if (on_legs && b.mode_time >= sp.crouch_time && b.mode_time < sp.crouch_time + sp.leg_time) {
    const dvec3 h = glm::normalize(horizontal(head));
    f.legs = sp.leg_force * (std::cos(sp.push_angle) * h + std::sin(sp.push_angle) * kUp);
  }
  f.total = f.wing[0] + f.wing[1] + f.wing[2] + f.wing[3] + f.tail + f.gravity + f.ground + f.legs;

  // --- Euler integration (eqs. 6-8, 13, 14).
  const dvec3 acceleration = f.total / sp.mass;
  b.position += b.velocity * dt;
  b.velocity += acceleration * dt;
  b.attitude = integrate_attitude(b.attitude, omega, dt);
  b.omega = omega + angular_acceleration(box_inertia(sp), f.torque) * dt;
  if (on_legs) {
    // The legs hold the bird on the ground: it sinks while crouching and cannot go below it.
    const double crouch = std::min(b.mode_time / std::max(sp.crouch_time, dt), 1.0);
    const double floor = w.ground_height + sp.stand_height - sp.crouch_depth * crouch;
    if (b.mode_time < sp.crouch_time) b.velocity = dvec3{0.0};
    if (b.position.y < floor) {
      b.position.y = floor;
      b.velocity.y = std::max(b.velocity.y, 0.0);
      if (b.mode_time < sp.crouch_time + sp.leg_time) b.velocity.x = b.velocity.z = 0.0;
    }
    b.omega = dvec3{0.0};
  }

  // --- Wingbeat and controller state to t + dt.
  b.phase = std::fmod(b.phase + 2.0 * kPi * b.frequency * dt, 2.0 * kPi);
  if (on_legs) {
    b.frequency = sp.f_max;
    b.amplitude = sp.amp_max;
  } else {
    b.frequency = frequency_step(sp, b.frequency, steering.height_error, dt);  // eq. 4
    b.amplitude = amplitude_step(sp, b.amplitude, steering.height_error, dt);  // eq. 5
  }
  b.tail_bend = approach(b.tail_bend, tail_cmd.bend, sp.tail_rate, dt);
  b.tail_twist = approach(b.tail_twist, tail_cmd.twist, sp.tail_rate, dt);
  b.mode_time += dt;
  if (on_legs && b.mode_time >= sp.crouch_time + sp.leg_time) {
    b.mode = FlightMode::flying;
    b.mode_time = 0.0;
  }
  if (out) *out = f;
}

}  // namespace aeroflock
