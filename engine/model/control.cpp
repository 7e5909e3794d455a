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

void turn_on(const Species& s, double bank, Steering& st) {
  if (std::fabs(bank) <= 0.5 * s.bank_max || std::fabs(st.heading_error) <= kBehind) return;
  const double turn = bank > 0.0 ? 1.0 : -1.0;
  if (st.heading_error * turn > 0.0) return;
  st.heading_error += turn * 2.0 * kPi;
  st.heading_error_ahead += turn * 2.0 * kPi;
}

double steer_share(const Species& s, double heading_error) {
  if (std::fabs(heading_error) <= s.dead_band) return 0.0;
  return std::clamp(heading_error / s.steer_full_error, -1.0, 1.0);
}

dvec3 crab_aim(const dvec3& to_goal, const dvec3& wind, double ground_speed) {
  const dvec3 way = horizontal(to_goal);
  const double length = glm::length(way);
  if (length == 0.0) return way;
  return way * (ground_speed / length) - horizontal(wind);
}

dvec3 track_aim(const dvec3& to_goal, const dvec3& wind, double airspeed) {
  const dvec3 way = horizontal(to_goal);
  const double length = glm::length(way);
  if (length == 0.0 || airspeed <= 0.0) return -horizontal(wind);
  const dvec3 along = way / length;
  const dvec3 w = horizontal(wind);
  const dvec3 across = w - along * glm::dot(along, w);
  const double across_speed = glm::length(across);
  if (across_speed >= airspeed) return across * (-airspeed / across_speed);
  return along * std::sqrt(airspeed * airspeed - across_speed * across_speed) - across;
}

dvec3 compensated_aim(const dvec3& to_goal, const dvec3& aim, double compensation) {
  const dvec3 way = horizontal(to_goal);
  if (compensation >= 1.0 || glm::length(way) == 0.0 || glm::length(aim) == 0.0) return aim;
  // Turned from the way by the share of the crab angle, in the x-z plane (y up).
  const double crab = std::atan2(way.x * aim.z - way.z * aim.x, way.x * aim.x + way.z * aim.z);
  const double a = compensation * crab;
  return dvec3{way.x * std::cos(a) - way.z * std::sin(a), 0.0,
               way.x * std::sin(a) + way.z * std::cos(a)};
}

double approach_speed(const Species& s, double to_branch) {
  if (to_branch < 0.0) return s.cruise_speed;
  const double room = std::max(0.0, to_branch - s.perch_radius);
  return std::min(s.cruise_speed,
                  std::sqrt(s.touchdown_speed * s.touchdown_speed + 2.0 * s.brake_decel * room));
}

Steering steer_towards(const Species& s, const glm::dquat& attitude, const dvec3& position,
                       const dvec3& velocity, const dvec3& goal, const dvec3& wind,
                       double ground_speed, bool by_course, bool commanded, bool in_air) {
  // Braking, the bird steers its course through the air (not its head, which a sideslip turns
  // away from it) onto the crab aim, so that it is not blown off the branch; barely moving
  // through the air, its head.
  const dvec3 air = velocity - wind;
  const double air_speed = std::hypot(air.x, air.z);
  const dvec3 head =
      by_course && air_speed > kSteerAirspeed ? air : attitude * dvec3{1.0, 0.0, 0.0};
  const dvec3 to_goal = goal - position;
  const dvec3 aim = crab_aim(to_goal, wind, ground_speed);
  // Flying faster through the air than the crab asks, or at an airspeed commanded otherwise, the
  // bird holds its track at its airspeed; towards a branch it holds it in full, lest it be blown
  // off it. A heading through the air (a flock's) is where it heads.
  const double aim_speed = glm::length(aim);
  dvec3 head_for = aim;
  if (in_air)
    head_for = horizontal(to_goal);
  else if (!by_course)
    head_for = compensated_aim(
        to_goal, commanded || air_speed > aim_speed ? track_aim(to_goal, wind, air_speed) : aim,
        s.drift_compensation);
  // Right of a horizontal direction (x, z) is (-z, x) in the world's x-z plane (y up).
  const double heading_error = std::atan2(-head.z * head_for.x + head.x * head_for.z,
                                          head.x * head_for.x + head.z * head_for.z);
  // The turn the bank is making, g tan(bank) / v, v the speed through the air (the bank's).
  const double turn_rate =
      air_speed > 1.0 ? kGravity * std::tan(bank_angle(attitude)) / air_speed : 0.0;
  return {heading_error, heading_error - s.heading_lead * turn_rate,
          to_goal.y - s.height_lead * velocity.y, aim_speed, air_speed};
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

double tail_twist_command(const Species& s, const Steering& st, bool fixed_rate) {
  return steer_share(s, fixed_rate ? st.heading_error : st.heading_error_ahead) * s.rot_max;
}

double commanded_airspeed(const Species& s, double command, double aim_speed, bool to_branch) {
  if (to_branch) return std::clamp(aim_speed, s.min_speed, s.max_speed);
  if (command > 0.0) return std::clamp(command, s.min_speed, s.max_speed);
  // No command: cruise_speed, or faster where that makes cruise_speed over the ground towards the
  // goal against the wind.
  return std::clamp(aim_speed, s.cruise_speed, s.max_speed);
}

double clearance_floor(const Species& s, double goal_height) {
  return std::min(s.clearance, goal_height);
}

Energy energy_errors(const Species& s, double height_error, double airspeed, double commanded,
                     double height, double goal_height) {
  // Below its goal, only the height it has above its clearance floor is there to trade for speed.
  const double room =
      goal_height > height ? std::max(height - clearance_floor(s, goal_height), 0.0) : INFINITY;
  const double deficit = (commanded * commanded - airspeed * airspeed) / (2.0 * kGravity);
  const double height_share =
      std::clamp((airspeed / s.min_speed - kSpeedFirst) / (1.0 - kSpeedFirst), 0.0, 1.0);
  return {height_error + deficit,
          height_share * std::clamp(height_error, -s.balance_band, s.balance_band) -
              std::min(deficit, room)};
}

double spool_lead(const Species& s, double amplitude, double air_climb) {
  if (s.K_a <= 0.0 || air_climb >= 0.0) return 0.0;
  return 0.5 * (s.amp_max - amplitude) / s.K_a * -air_climb;
}

double speed_lead_error(const Species& s, double airspeed, double airspeed_rate) {
  return -s.speed_lead * airspeed * airspeed_rate / kGravity;
}

double commanded_pitch(const Species& s, double pitch_trim, double balance, double height,
                       double goal_height) {
  const double pitch = std::clamp(pitch_trim + s.balance_gain * balance, s.pitch_min, s.pitch_max);
  const double floor = clearance_floor(s, goal_height);
  if (height >= floor) return pitch;
  return std::max(pitch, s.climb_pitch * (1.0 - height / floor));
}

bool heeds_wind(const Species& s, double speed) {
  return speed > kTouchdownAim * s.touchdown_speed;
}

double perch_airspeed(const Species& s, const dvec3& to_perch, const dvec3& wind) {
  return glm::length(crab_aim(to_perch, wind, kTouchdownAim * s.touchdown_speed));
}

double flare_share(const Species& s, double airspeed, double to_airspeed, double to_perch) {
  const double room = std::max(to_perch - 0.5 * s.perch_radius, 0.1 * s.perch_radius);
  const double needed =
      std::max(0.0, airspeed * airspeed - to_airspeed * to_airspeed) / (2.0 * room);
  return std::min(needed / s.flare_decel, 1.0);
}

double flare_pitch(const Species& s, double pitch_trim, double share) {
  return std::clamp(pitch_trim + (s.brake_pitch - pitch_trim) * share, s.pitch_min, s.brake_pitch);
}

bool hovers(const Species& s) { return s.hover_final != 0.0; }

namespace {
// How far along the final's aim a bird `to_point` from the point is: 0 at kFinalTo perch radii, 1
// at kFinalFrom (unclamped).
double final_share(const Species& s, double to_point) {
  return (to_point / s.perch_radius - kFinalTo) / (kFinalFrom - kFinalTo);
}
}  // namespace

double final_aim(const Species& s, double to_point) {
  const double u = std::clamp(final_share(s, to_point), 0.0, 1.0);
  return s.perch_radius * (kEndAbove + (kApproachAbove - kEndAbove) * u * u * (3.0 - 2.0 * u));
}

dvec3 final_track(const Species& s, const dvec3& way, const dvec3& velocity) {
  const double d = glm::length(horizontal(way));
  // Within kHoldHeading radii it heads on (in a wind, for the point itself); the aim fades in over
  // the next kHoldHeading radii out.
  const double hold = kHoldHeading * s.perch_radius;
  const double fade = std::clamp((d - hold) / hold, 0.0, 1.0);
  if (!(s.final_track_lead > 0.0 && fade > 0.0)) return dvec3{0.0};
  const dvec3 to = horizontal(way) / d;
  const dvec3 across = horizontal(velocity) - to * glm::dot(horizontal(velocity), to);
  return -across * fade *
         std::min(s.final_track_lead, d / std::max(glm::length(horizontal(velocity)), 1.0));
}

double final_aim_rate(const Species& s, const dvec3& way, const dvec3& velocity) {
  const double d = glm::length(horizontal(way));
  const double u = final_share(s, d);
  if (!(u > 0.0 && u < 1.0)) return 0.0;
  const double closing = glm::dot(horizontal(way), horizontal(velocity)) / d;
  return -(kApproachAbove - kEndAbove) * 6.0 * u * (1.0 - u) / (kFinalFrom - kFinalTo) * closing;
}

double final_speed(const Species& s, double to_perch, double to_point) {
  const double end = kFinalSpeed * s.touchdown_speed;
  return std::min(approach_speed(s, to_perch),
                  std::sqrt(end * end + 2.0 * kFinalDecel * s.brake_decel * to_point));
}

double final_climb(double height_error, double aim_rate) {
  const double sink = std::sqrt(2.0 * kFinalSinkDecel * std::max(-height_error, 0.0));
  return std::clamp(kFinalClimbGain * height_error, -sink, kFinalClimbMax) + aim_rate;
}

double hover_share(double airspeed) {
  return std::clamp((kHoverAirspeed - airspeed) / kHoverBand, 0.0, 1.0);
}

double hover_pitch(const Species& s, double airspeed, double along, double wanted) {
  const double up = std::min(std::atan(kHoverLift / (airspeed + kHoverLiftSpeed)), kHoverBasePitch);
  return std::clamp(up + kHoverPitchGain * (along - wanted), 0.0, s.hover_pitch_max);
}

double hover_incidence(const Species& s, double along, double wanted) {
  if (!(s.hover_incidence > 0.0)) return 0.0;
  return std::clamp(s.hover_incidence + kHoverIncidenceGain * (along - wanted), 0.0,
                    kHoverIncidenceMax);
}

double final_amplitude(const Species& s, double amplitude, double energy_error) {
  return std::clamp(amplitude + kFinalAmplitudeGain * energy_error, s.amp_min, s.amp_max);
}

void final_wingbeat(const Species& s, double energy_error, double used, double hover,
                    double& frequency, double& amplitude, double dt) {
  const double share = std::clamp(energy_error / (kFinalBand * s.perch_radius), -1.0, 1.0);
  amplitude =
      std::clamp(amplitude + kFinalAmplitudeRate * s.K_a * share * dt, s.amp_min, s.amp_max);
  // The frequency trims within a band a tenth of the amplitude's range wide.
  const double range = s.amp_max - s.amp_min;
  const double trim =
      std::clamp((used - s.amp_min - kFinalTrimLow * range) / (0.1 * range), -1.0, 1.0);
  // At full amplitude and still short of its climb, a bird that may (final_beats_faster) quickens.
  const bool quickens = s.final_beats_faster != 0.0 && used >= s.amp_max && share > 0.0;
  const double rate = hover > 0.5 || quickens ? kFinalFrequencyRate : kFinalTrimRate * trim;
  frequency = std::clamp(frequency + rate * s.K_f * dt, s.f_min, s.f_max);
}

double go_round_pitch(const Species& s, double airspeed) {
  const double share = 1.0 - airspeed / (0.5 * s.min_speed);
  return share > 0.0 ? s.brake_pitch * std::min(share, 1.0) : -kPi;
}

PitchControl pitch_control(const Species& s, double pitch_command, double pitch, double rate) {
  const double error = pitch_command - pitch - s.pitch_damping * rate;
  const double beyond = error - std::clamp(error, -s.pitch_band, s.pitch_band);
  return {std::clamp(s.pitch_gain * beyond, -s.bend_max, s.bend_max),
          std::clamp(s.sweep_gain * error, -s.sweep_max, s.sweep_max)};
}

// The head (body x) and right wing (body z) turn at omega_world x axis; pitch = asin(head.y),
// bank = asin(-right.y).
double pitch_rate(const glm::dquat& attitude, const dvec3& omega) {
  const dvec3 head = attitude * dvec3{1.0, 0.0, 0.0};
  const double c = std::sqrt(std::max(1.0 - head.y * head.y, 1e-6));
  return glm::cross(attitude * omega, head).y / c;
}

double bank_rate(const glm::dquat& attitude, const dvec3& omega) {
  const dvec3 right = attitude * dvec3{0.0, 0.0, 1.0};
  const double c = std::sqrt(std::max(1.0 - right.y * right.y, 1e-6));
  return -glm::cross(attitude * omega, right).y / c;
}

double roll_for_bank(const Species& s, const glm::dquat& attitude, const dvec3& omega,
                     double bank_command) {
  const double wanted = (bank_command - bank_angle(attitude)) / s.bank_time;
  const dvec3 others{0.0, omega.y, omega.z};
  // The bank rate is linear in omega.x: d(bank rate)/d(omega.x) = bank_rate of a pure roll.
  const double per_roll = bank_rate(attitude, dvec3{1.0, 0.0, 0.0});
  const double roll =
      std::fabs(per_roll) > 0.1 ? (wanted - bank_rate(attitude, others)) / per_roll : wanted;
  return std::clamp(roll, -s.roll_rate, s.roll_rate);
}

double approach(double angle, double command, double rate, double dt) {
  const double step = rate * dt;
  return angle + std::clamp(command - angle, -step, step);
}

double full_bank_radius(const Species& s, double speed) {
  return kWideTurn * speed * speed / (kGravity * std::tan(s.bank_max));
}

bool circles_goal(double heading_error, double distance, double radius, double speed, double rise,
                  double wind) {
  // In a wind the circle drifts over the goal: by more than its radius each turn (2 pi radius /
  // speed long) once the wind is faster than speed / (2 pi).
  if (2.0 * kPi * wind >= speed) return false;
  // The circle's centre lies `radius` abeam; the goal inside it when d < 2 radius |sin(phi)|.
  return std::fabs(rise) < kLevelGoal * distance &&
         distance < 2.0 * radius * std::fabs(std::sin(heading_error));
}

double heading_bank(const Species& s, double heading_error, double distance, double speed,
                    double dead_band) {
  if (std::fabs(heading_error) <= dead_band) return 0.0;
  if (std::fabs(heading_error) >= 0.5 * kPi) return heading_error > 0.0 ? s.bank_max : -s.bank_max;
  double rate = heading_error / s.turn_time;
  // Pure pursuit, curvature 2 sin(phi) / distance: the circle through a near goal.
  // No tighter than the circle the bird flies at full bank.
  const double tightest = speed * speed / (kGravity * std::tan(s.bank_max));
  const double pursuit = 2.0 * speed * std::sin(heading_error) / std::max(distance, tightest);
  if (std::fabs(pursuit) > std::fabs(rate)) rate = pursuit;
  return coordinated_bank(s, rate, speed);
}

double recovery_bank(const Species& s, double pitch, double descent, double airspeed) {
  const double by_pitch = (kSteepPitch - std::fabs(pitch)) / (kSteepPitch / 2.0);
  const double by_descent = (kSteepDescent - descent) / (kSteepDescent / 2.0);
  const double by_speed = (kDiveSpeed * s.max_speed - airspeed) / (0.5 * s.max_speed);
  return s.bank_max * std::clamp(std::min({by_pitch, by_descent, by_speed}), 0.0, 1.0);
}

double descent_angle(double air_climb, double airspeed) {
  return airspeed > 0.0 ? std::max(0.0, -std::asin(std::clamp(air_climb / airspeed, -1.0, 1.0)))
                        : 0.0;
}

double ground_bank(const Species& s, double height) {
  return std::asin(std::clamp(height / s.wing_length, 0.0, 1.0));
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
