#include "control.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "body.h"
#include "constants.h"

namespace aeroflock {

using glm::dvec3;

double sign_outside(double x, double band) {
  if (x > band) return 1.0;
  if (x < -band) return -1.0;
  return 0.0;
}

double steer_share(const Species& s, double heading_error) {
  if (std::fabs(heading_error) <= s.dead_band) return 0.0;
  return std::clamp(heading_error / s.steer_full_error, -1.0, 1.0);
}

Steering steer_towards(const Species& s, const glm::dquat& attitude, const dvec3& position, const dvec3& velocity, const dvec3& goal) {
  const dvec3 head = attitude * dvec3{1.0, 0.0, 0.0};
  const dvec3 to_goal = goal - position;
  // Right of a horizontal direction (x, z) is (-z, x) in the world's x-z plane (y up).
  auto angle_to_goal = [&](const dvec3& d) {
    return std::atan2(-d.z * to_goal.x + d.x * to_goal.z, d.x * to_goal.x + d.z * to_goal.z);
  };
  const double heading_error = angle_to_goal(head);
  const double speed = std::hypot(velocity.x, velocity.z);
  // The turn the bank is making, g tan(bank) / v.
  const double turn_rate = speed > 1.0 ? kGravity * std::tan(bank_angle(attitude)) / speed : 0.0;
  return {heading_error, heading_error - s.heading_lead * turn_rate,
          to_goal.y - s.height_lead * velocity.y};
}

namespace {
double rate_step(double value, double lo, double hi, double rate, double dy, double dt) {
  const double sign = dy > 0.0 ? 1.0 : (dy < 0.0 ? -1.0 : 0.0);
  return std::clamp(value + sign * rate * dt, lo, hi);
}
}  // namespace

double frequency_step(const Species& s, double frequency, double dy, double dt) {
  return rate_step(frequency, s.f_min, s.f_max, s.K_f, dy, dt);
}

double amplitude_step(const Species& s, double amplitude, double dy, double dt) {
  return rate_step(amplitude, s.amp_min, s.amp_max, s.K_a, dy, dt);
}

TailCommand tail_command(const Species& s, const Steering& st, bool fixed_rate) {
  return {sign_outside(st.height_error, s.height_band) * s.bend_max,
          steer_share(s, fixed_rate ? st.heading_error : st.heading_error_ahead) * s.rot_max};
}

double approach(double angle, double command, double rate, double dt) {
  const double step = rate * dt;
  return angle + std::clamp(command - angle, -step, step);
}

double pursuit_bank(const Species& s, double heading_error, double distance, double speed) {
  if (std::fabs(heading_error) <= s.dead_band) return 0.0;
  if (std::fabs(heading_error) >= 0.5 * kPi || distance <= 0.0)
    return heading_error > 0.0 ? s.bank_max : -s.bank_max;
  // No tighter than the circle the bird flies at full bank.
  const double tightest = speed * speed / (kGravity * std::tan(s.bank_max));
  return coordinated_bank(s, 2.0 * speed * std::sin(heading_error) / std::max(distance, tightest), speed);
}

double coordinated_bank(const Species& s, double turn_rate, double speed) {
  return std::clamp(std::atan(speed * turn_rate / kGravity), -s.bank_max, s.bank_max);
}

dvec3 landing_point(const dvec3& bird, const dvec3& heading, const dvec3& branch_point,
                    const dvec3& branch_direction) {
  // Work in the horizontal plane: Q1 + s h = Q2 + t n, with n perpendicular to the branch.
  const double hx = heading.x, hz = heading.z;
  const double hn = std::hypot(hx, hz);
  if (hn == 0.0) return branch_point;
  const double nx = -branch_direction.z, nz = branch_direction.x;
  const double det = (hx / hn) * (-nz) - (hz / hn) * (-nx);  // | h  -n |
  if (std::fabs(det) < kLinedUpSine) return branch_point;
  const double dx = branch_point.x - bird.x, dz = branch_point.z - bird.z;
  const double s = (dx * (-nz) - dz * (-nx)) / det;  // Cramer's rule for s
  if (s <= 0.0 || s > kFarthestCrossing * std::hypot(dx, dz)) return branch_point;
  const dvec3 q3{bird.x + s * hx / hn, branch_point.y, bird.z + s * hz / hn};
  return 0.25 * bird + 0.5 * q3 + 0.25 * branch_point;
}

dvec3 landing_curve(const dvec3& q1, const dvec3& p, const dvec3& q2, double u) {
  const dvec3 q3 = 2.0 * p - 0.5 * (q1 + q2);
  const double v = 1.0 - u;
  return v * v * q1 + 2.0 * u * v * q3 + u * u * q2;
}

double landing_progress(const dvec3& q1, const dvec3& p, const dvec3& q2, double u,
                        const dvec3& position, double lookahead) {
  constexpr double kStep = 1.0 / 128.0;
  const dvec3 q3 = 2.0 * p - 0.5 * (q1 + q2);
  while (u < 1.0) {
    const dvec3 at = landing_curve(q1, p, q2, u);
    const dvec3 tangent = (1.0 - u) * (q3 - q1) + u * (q2 - q3);
    const bool behind = glm::dot(at - position, tangent) < 0.0;
    if (!behind && glm::distance(at, position) >= lookahead) break;
    u = std::min(1.0, u + kStep);
  }
  return u;
}

}  // namespace aeroflock
