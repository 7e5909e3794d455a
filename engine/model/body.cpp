#include "body.h"

#include <algorithm>
#include <cmath>

#include "constants.h"

namespace aeroflock {

using glm::dquat;
using glm::dvec3;

dquat integrate_attitude(const dquat& q, const dvec3& omega_body, double dt) {
  const dquat w(0.0, omega_body.x, omega_body.y, omega_body.z);
  const dquat dq = q * w;
  const double h = 0.5 * dt;
  return glm::normalize(dquat(q.w + h * dq.w, q.x + h * dq.x, q.y + h * dq.y, q.z + h * dq.z));
}

dvec3 angular_acceleration(const Inertia& inertia, const dvec3& torque) {
  return {torque.x / inertia.x, torque.y / inertia.y, torque.z / inertia.z};
}

double ground_effect_floor(const Species& s) { return 0.5 * s.box_b; }

double ground_effect_force(const Species& s, double height) {
  // eq. 15 grows without bound as h -> 0: a bird spawned 1e-6 m above the ground was thrown up
  // at 585 m/s. Its body box (eq. 12) is box_b tall, so its centre is never nearer the ground
  // than box_b / 2 while the body is above it (the presets stand and crouch higher still): eq. 15
  // is evaluated no nearer than that, at most k / (box_b / 2) times the weight.
  if (height > 0.0 && height < s.wing_length)
    return s.ground_k * kGravity * s.mass / std::max(height, ground_effect_floor(s));
  return 0.0;
}

double bank_angle(const dquat& attitude) {
  const dvec3 right = attitude * dvec3{0.0, 0.0, 1.0};
  return std::asin(std::clamp(-right.y, -1.0, 1.0));
}

double pitch_angle(const dquat& attitude) {
  const dvec3 head = attitude * dvec3{1.0, 0.0, 0.0};
  return std::asin(std::clamp(head.y, -1.0, 1.0));
}

dquat heading_attitude(double heading) { return glm::angleAxis(-heading, dvec3{0.0, 1.0, 0.0}); }

glm::dquat level_attitude(const glm::dquat& q) { return facing(q * glm::dvec3{1.0, 0.0, 0.0}); }

glm::dquat facing(const glm::dvec3& head) {
  const double n = std::hypot(head.x, head.z);
  if (!(n > 0.0)) return glm::dquat{1.0, 0.0, 0.0, 0.0};  // head straight up or down: facing +x
  const double hx = head.x / n, hz = head.z / n;
  // The half-way quaternion between +x and h, (w, y) = (1 + hx, -hz) normalised; facing back
  // (hx < 0) the same rotation as (|hz|, -sgn(hz) (1 - hx)), which has no cancellation.
  const double w = hx >= 0.0 ? 1.0 + hx : std::fabs(hz);
  const double y = hx >= 0.0 ? -hz : (hz < 0.0 ? 1.0 - hx : hx - 1.0);
  const double len = std::hypot(w, y);
  return glm::dquat{w / len, 0.0, y / len, 0.0};
}

void come_to_rest(BirdState& b, const glm::dvec3& at) {
  b.position = at;
  b.velocity = glm::dvec3{0.0};
  b.omega = glm::dvec3{0.0};
  b.attitude = level_attitude(b.attitude);
  b.amplitude = 0.0;
  b.tail_bend = 0.0;
  b.tail_twist = 0.0;
}

void hold_on(BirdState& b, FlightMode mode, const glm::dvec3& at) {
  b.mode = mode;
  b.mode_steps = 0;
  b.landing_stage = LandingStage::settling;
  b.via_point = at;
}

double turn_angle(const glm::dquat& a, const glm::dquat& b) {
  // acos(w) as atan2: well conditioned near w = 1, a body all but turned to `b`.
  const double w = std::min(1.0, std::fabs(glm::dot(a, b)));
  return 2.0 * std::atan2(std::sqrt(1.0 - w * w), w);
}

glm::dquat turn_towards(const glm::dquat& q, const glm::dquat& to, double angle) {
  glm::dquat r = to * glm::conjugate(q);
  if (r.w < 0.0) r = -r;  // the shorter way round
  const double s = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
  if (s == 0.0 || 2.0 * std::atan2(s, r.w) <= angle) return to;
  const double c = std::cos(0.5 * angle), k = std::sin(0.5 * angle) / s;
  return glm::normalize(glm::dquat{c, k * r.x, k * r.y, k * r.z} * q);
}

}  // namespace aeroflock
