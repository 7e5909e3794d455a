#include "step.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "aerodynamics.h"
#include "body.h"
#include "constants.h"
#include "control.h"
#include "route.h"
#include "tail.h"
#include "wake.h"
#include "wingbeat.h"

namespace aeroflock {
namespace {

using glm::dquat;
using glm::dvec3;

const dvec3 kUp{0.0, 1.0, 0.0};

// What the controller decides from the state at time t (paper 3.4, 4.1-4.4).
struct Commands {
  Steering steering;
  double energy_error;  // what eqs. 4, 5 follow, cm
  double balance;       // what the pitch trim integrates, cm
  double bend, twist;   // where the tail moves to
  double sweep;         // where the wings' sweep moves to
  double incidence;     // the arms' added incidence (braking)
  bool final;           // hovering onto the perch point (Species::hover_final)
  double hover;         // how much, in [0, 1] (control.h: hover_share)
  double amplitude;     // the wingbeat's amplitude this step (the final's answers at once)
  double opening;       // the tail's opening now, eq. 10 (fully open while braking)
  dvec3 omega;          // body rates used this step, with the controller's kinematic ones
  bool circling;        // the goal lies inside the full-bank circle
};

Commands control(const BirdState& b, const Species& sp, const World& w, double dt, dvec3 goal,
                 double airspeed_command, bool in_air) {
  // No bird flies lower than it stands: a goal on (or under) the ground is flown to at that height.
  // A bird gliding down its glide path to its site on the ground aims on under it (route.h:
  // route_goal); not one steering by its flock.
  const std::optional<dvec3> way = way_to_perch(b, sp, w);
  const double ground = w.ground_height + sp.stand_height;
  if (!(way && lands_on_ground(sp) && !in_air)) goal.y = std::max(goal.y, ground);
  const bool on_legs = b.mode == FlightMode::taking_off;
  const bool braking = b.mode == FlightMode::landing;
  // Braking, the bird aims above the perch: slowing, it sinks onto it (below, it could not climb).
  // Hovering onto it (the final), it aims above by less and less, and on its way in already above.
  const bool final = braking && way && hovers(sp);
  const double to_point = way ? glm::length(horizontal(*way)) : -1.0;
  if (final) {
    goal.y += final_aim(sp, to_point);
    goal += final_track(sp, *way, b.velocity);
  } else if (braking)
    goal.y += kFlareAimAbove * sp.perch_radius;
  else if (way && hovers(sp) && !in_air)
    goal.y += kApproachAbove * sp.perch_radius;
  const bool fixed_rate = w.turning == TurningModel::fixed_rate && !braking;
  const double to_perch = way ? glm::length(*way) : -1.0;
  const dvec3 wind = wind_at(w, b.position.y);
  Commands c;
  c.final = final;
  // On its legs a bird's air is the wind alone: it has no airspeed yet to hold a track at.
  const double ground_speed =
      final ? final_speed(sp, to_perch, to_point) : approach_speed(sp, to_perch);
  c.steering = steer_towards(sp, b.attitude, b.position, b.velocity, goal, wind, ground_speed,
                             braking, airspeed_command > 0.0 && !on_legs, in_air);
  // Close by the point in calm air it heads on (steering for the point it would turn about it).
  if (final && to_point < kHoldHeading * sp.perch_radius &&
      !heeds_wind(sp, glm::length(horizontal(wind)))) {
    c.steering.heading_error = 0.0;
    c.steering.heading_error_ahead = 0.0;
  }
  // The tail twist steers the tail model; with fixed-rate turning it only shows the turn. It
  // twists towards the turn but never stands on edge: bank plus twist stay within
  // tail_roll_max, so that the tail still holds the body's pitch in a steep turn.
  const double bank = bank_angle(b.attitude);
  const double pitch = pitch_angle(b.attitude);
  // A target well behind is turned to the way the bird banks (turn_on); the landing curve and
  // gate have their own go-rounds (route.cpp).
  const bool to_target = !way && b.landing_stage == LandingStage::none;
  if (to_target && !fixed_rate) turn_on(sp, bank, c.steering);
  c.twist =
      std::clamp(tail_twist_command(sp, c.steering, fixed_rate),
                 std::min(0.0, -sp.tail_roll_max - bank), std::max(0.0, sp.tail_roll_max - bank));
  c.opening = tail_opening(sp, b);

  // Energy: the wingbeat feeds the total, the pitch shares it between height and airspeed.
  const double airspeed = glm::length(b.velocity - wind);
  const double air_climb = b.velocity.y - wind.y;
  const double commanded =
      commanded_airspeed(sp, airspeed_command, c.steering.aim_speed, to_perch >= 0.0);
  const Energy e = energy_errors(sp, c.steering.height_error, airspeed, commanded,
                                 b.position.y - ground, goal.y - ground);
  // Braking, the flare sets the pitch and the air slows the bird: the wingbeat holds its height
  // (eqs. 4, 5 as the paper has them). Otherwise it looks ahead by what the bird sinks while it
  // answers (spool_lead).
  // The final: the height a commanded climb's error makes in kFinalLead (control.h: final_climb).
  c.energy_error =
      final
          ? kFinalLead * (final_climb(goal.y - b.position.y, final_aim_rate(sp, *way, b.velocity)) -
                          b.velocity.y)
      : braking ? c.steering.height_error
                : e.total + spool_lead(sp, b.amplitude, air_climb) +
                      (in_air ? speed_lead_error(sp, airspeed, b.airspeed_rate) : 0.0);
  // Pitched up well past the most it commands, the wingbeat's nose-up moment is winning: the
  // bird beats no harder (eqs. 4, 5 hold frequency and amplitude) rather than loop. Easing it
  // would stall the climb of a bird whose shoulder sits forward: a nose-high climb needs it.
  if (!final && pitch > (braking ? sp.brake_pitch : sp.pitch_max) + kPitchOverrun)
    c.energy_error = std::min(c.energy_error, 0.0);
  // Pitched down well past the least it commands, the glide's nose-down moment is winning: the
  // bird beats its wings harder rather than dive on.
  if (pitch < sp.pitch_min - kPitchOverrun) c.energy_error = std::max(c.energy_error, 1.0);
  c.balance = e.balance;
  // Braking, the wings meet the air at a high angle of attack (docs/MODEL.md) as the body pitches
  // up: the arms' incidence rises by brake_incidence at full flare, over bank_time.
  const double flare =
      braking && way ? flare_share(sp, airspeed, perch_airspeed(sp, *way, wind), to_perch) : 0.0;
  // The final at a low airspeed hovers: its pitch holds its speed over the ground along its head
  // to the profile's (final_speed: towards the point, or back to it once past), with the wings at
  // their own incidence (or braking too: hover_incidence); faster through the air it flares. Both
  // read the ground velocity over its last wingbeat (its speed then, its direction now), not a
  // wingbeat's surge.
  dvec3 beat_track = horizontal(b.velocity);
  if (final && glm::length(beat_track) > 0.0)
    beat_track *= last_beat_speed(b) / glm::length(b.velocity);
  const double hover_airspeed = glm::length(beat_track - horizontal(wind));
  c.hover = final ? hover_share(hover_airspeed) : 0.0;
  c.incidence =
      (1.0 - c.hover) * sp.brake_incidence * flare * std::min(mode_time(b, dt) / sp.bank_time, 1.0);
  double hovering = 0.0;
  if (c.hover > 0.0) {
    const dvec3 head = horizontal(b.attitude * dvec3{1.0, 0.0, 0.0});
    const dvec3 along = glm::length(head) > 0.0 ? head / glm::length(head) : head;
    const double wanted =
        glm::dot(horizontal(*way), along) < 0.0 ? -kFinalSpeed * sp.touchdown_speed : ground_speed;
    const double speed_along = glm::dot(beat_track, along);
    hovering = hover_pitch(sp, hover_airspeed, speed_along, wanted);
    // A heavy bird brakes with its wings as well: its pitch is slow to answer.
    c.incidence += c.hover * hover_incidence(sp, speed_along, wanted);
  }
  // On its legs the bird cannot pitch: it holds its tail and sweep neutral, so that it leaves
  // the ground trimmed rather than wound up to pitch up. Going round from a hover it keeps its
  // nose up until it has speed (control.h: go_round_pitch).
  const double pitch_command =
      on_legs   ? pitch
      : braking ? c.hover * hovering + (1.0 - c.hover) * flare_pitch(sp, b.pitch_trim, flare)
                : std::max(hovers(sp) ? go_round_pitch(sp, airspeed) : -kPi,
                           commanded_pitch(sp, b.pitch_trim, e.balance, b.position.y - ground,
                                           goal.y - ground));
  // Hovering, the wingbeat swings the pitch rate within each beat: damped on it in full, the
  // tail and sweep would chatter between their limits.
  const PitchControl p = pitch_control(
      sp, pitch_command, pitch, (1.0 - kHoverDamping * c.hover) * pitch_rate(b.attitude, b.omega));
  c.bend = p.bend;
  c.sweep = p.sweep;
  c.amplitude = final ? final_amplitude(sp, b.amplitude, c.energy_error) : b.amplitude;

  // Kinematic body rates: the bank (both turning models), the yaw at the standard rate R
  // (fixed-rate model, eq. 3). Pitch and the rest come from the torque.
  c.omega = b.omega;
  c.circling = false;
  if (on_legs) {
    c.omega = dvec3{0.0};
    return c;
  }
  // A coordinated turn banks for the speed through the air.
  const double speed = c.steering.air_speed;
  const double turn_rate = sign_outside(c.steering.heading_error, sp.dead_band) * sp.turn_rate;
  double bank_cmd = 0.0;
  if (fixed_rate)
    bank_cmd = coordinated_bank(sp, turn_rate, speed);
  else {
    const double distance = glm::length(horizontal(goal - b.position));
    const double circle = full_bank_radius(sp, speed);
    c.circling = to_target && circles_goal(c.steering.heading_error_ahead, distance, circle, speed,
                                           goal.y - b.position.y, glm::length(horizontal(wind)));
    // Circling such a goal for kCirclingTurn of a turn, the bird flies on with its wings level
    // until it can turn onto the goal. Sooner, it would not turn onto a goal it only just missed
    // (Fig. 16's eagle would fly off its circle of targets).
    if (!(c.circling && b.circling_steps * dt > kCirclingTurn * 2.0 * kPi * circle / speed))
      bank_cmd = heading_bank(sp, c.steering.heading_error_ahead, distance, speed,
                              c.hover > 0.5 ? 0.0 : sp.dead_band);
  }
  // Hovering, its body is steep: banked a little, it turns about the vertical.
  const double most =
      std::min(ground_bank(sp, b.position.y - w.ground_height),
               std::max(recovery_bank(sp, pitch, descent_angle(air_climb, airspeed), airspeed),
                        c.hover * kHoverBank));
  bank_cmd = std::clamp(bank_cmd, -most, most);
  if (fixed_rate) {
    // eq. 3: the heading turns at -sgn(phi) R about the vertical.
    dvec3 world_rate = b.attitude * c.omega;
    world_rate.y = -turn_rate;
    c.omega = glm::conjugate(b.attitude) * world_rate;
  }
  c.omega.x = roll_for_bank(sp, b.attitude, c.omega, bank_cmd);
  return c;
}

// The air the wakes that bird b meets (seen->wake, at step `step`) move at its four wing points
// (WingForces::force's order) and its tail (`tail`, body frame), body frame. Its flock's birds are
// of its species.
struct WakeAir {
  dvec3 wing[4];
  dvec3 tail;
};
WakeAir wake_air(const BirdState& b, const Species& sp, const World& w, const Perception& seen,
                 uint64_t step, double dt, const WingPoint right[2], const dvec3& tail,
                 const glm::dmat3& to_world, const glm::dmat3& to_body) {
  dvec3 at[5];
  for (int i = 0; i < 2; ++i) {
    at[i] = right[i].position;
    at[2 + i] = mirror_to_left(right[i]).position;
  }
  at[4] = tail;
  WakeAir air{};
  dvec3* out[5] = {&air.wing[0], &air.wing[1], &air.wing[2], &air.wing[3], &air.tail};
  for (uint32_t k = 0; k < seen.wakes; ++k) {
    const WakeSource& was = seen.wake[k];
    const WakeSource now = wake_now(was, seen.wake_step, step, dt, wind_at(w, was.position.y));
    for (int p = 0; p < 5; ++p)
      *out[p] += to_body * wake_velocity(sp, now, b.position + to_world * at[p]);
  }
  return air;
}

// The frequency at which bird b's wingbeat runs: its own, and faster or slower as formation
// flying shifts its phase (seen->phase_rate).
double beat_frequency(const BirdState& b, const Perception* seen) {
  return b.frequency + (seen ? seen->phase_rate / (2.0 * kPi) : 0.0);
}

// Forces at time t (eqs. 1, 2 at the five points, 11, 15, the legs) and the torque on the body;
// with the wakes the bird meets (seen, at step `step`) in the air at the five points.
StepForces forces(const BirdState& b, const Species& sp, const World& w, double dt,
                  const Commands& c, const Perception* seen, uint64_t step) {
  StepForces f;
  const glm::dmat3 to_world = glm::mat3_cast(b.attitude);
  const glm::dmat3 to_body = glm::transpose(to_world);
  const dvec3 body_velocity = to_body * b.velocity;
  const dvec3 body_wind = to_body * wind_at(w, b.position.y);
  const TailGeometry tg = tail_geometry(sp, b.tail_bend, b.tail_twist);
  WingPoint right[2];
  right_wing_points(sp, b.phase, c.amplitude, beat_frequency(b, seen), b.sweep, c.incidence, right);
  const bool wakes = seen && seen->wakes > 0;
  const WakeAir wake =
      wakes ? wake_air(b, sp, w, *seen, step, dt, right, tg.position, to_world, to_body)
            : WakeAir{};
  const WingForces wings =
      wing_forces_at(sp, right, body_wind - body_velocity, c.omega, wakes ? wake.wing : nullptr);
  for (int i = 0; i < 4; ++i) f.wing[i] = to_world * wings.force[i];
  f.torque = wings.torque;
  const WingPoint at[4] = {right[0], right[1], mirror_to_left(right[0]), mirror_to_left(right[1])};
  for (int i = 0; i < 4; ++i) f.power -= glm::dot(wings.force[i], at[i].velocity);
  if (wakes)
    f.wake_air = to_world * ((wake.wing[0] + wake.wing[1] + wake.wing[2] + wake.wing[3]) / 4.0);
  const dvec3 tail_air = body_wind - body_velocity - glm::cross(c.omega, tg.position) + wake.tail;
  const dvec3 tail = aerodynamic_force(sp, tail_air, tg.chord, tg.normal, tail_area(sp, c.opening));
  f.tail = to_world * tail;
  f.tail_torque = glm::cross(tg.position, tail);  // eq. 11
  f.torque += f.tail_torque;
  f.gravity = dvec3{0.0, -sp.mass * kGravity, 0.0};
  if (w.ground_effect) f.ground = kUp * ground_effect_force(sp, b.position.y - w.ground_height);
  const double in_mode = mode_time(b, dt);
  if (b.mode == FlightMode::taking_off && in_mode >= sp.crouch_time &&
      in_mode < sp.crouch_time + sp.leg_time) {
    const dvec3 ahead = glm::normalize(horizontal(to_world[0]));
    f.legs = sp.leg_force * (std::cos(sp.push_angle) * ahead + std::sin(sp.push_angle) * kUp);
  }
  f.total = f.wing[0] + f.wing[1] + f.wing[2] + f.wing[3] + f.tail + f.gravity + f.ground + f.legs;
  return f;
}

// While taking off the legs hold the bird on the ground: it sinks while crouching, pushes off
// with its legs, and cannot go below the ground.
void stand_on_legs(BirdState& b, const Species& sp, const World& w, double dt) {
  const double in_mode = mode_time(b, dt);
  const double crouch = std::min(in_mode / std::max(sp.crouch_time, dt), 1.0);
  const double floor = w.ground_height + sp.stand_height - sp.crouch_depth * crouch;
  if (in_mode < sp.crouch_time) {
    b.velocity = dvec3{0.0};
    b.position.y = floor;
  }
  if (b.position.y < floor) {
    b.position.y = floor;
    b.velocity.y = std::max(b.velocity.y, 0.0);
    if (in_mode < sp.crouch_time + sp.leg_time) b.velocity.x = b.velocity.z = 0.0;
  }
  b.omega = dvec3{0.0};
}

// A bird holding on (perched, or standing after a touch-down) settles onto `b.via_point`, where it
// sits: its legs pull its centre there as a critically damped spring whose pull is at most
// kSettleDecel, its body turns level at kSettleTurn at most, its wings fold and its tail closes at
// their own rates while the wingbeat runs down. Before (issue 40) a grip put it there, still and
// level, in one step.
void settle(BirdState& b, const Species& sp, const World& w, double dt) {
  const dvec3 off = b.position - b.via_point;
  dvec3 pull = -kSettleStiffness * off - 2.0 * std::sqrt(kSettleStiffness) * b.velocity;
  const double strength = glm::length(pull);
  if (strength > kSettleDecel) pull *= kSettleDecel / strength;
  b.velocity += pull * dt;
  b.position += b.velocity * dt;
  // On the ground its legs fold at most until its body rests on it (a hard touch-down stops
  // there). So too a bird that lands on the ground, on its site (perched there: its place is on
  // it).
  const double floor = w.ground_height + std::min(0.5 * sp.box_b, sp.stand_height);
  const bool on_ground = lands_on_ground(sp) && b.via_point.y <= w.ground_height + sp.stand_height;
  if ((b.mode == FlightMode::standing || on_ground) && b.position.y < floor) {
    b.position.y = floor;
    b.velocity.y = std::max(b.velocity.y, 0.0);
  }
  const glm::dquat level = level_attitude(b.attitude);
  b.attitude = turn_towards(b.attitude, level, kSettleTurn * dt);
  b.omega = dvec3{0.0};
  b.phase = std::fmod(b.phase + 2.0 * kPi * b.frequency * dt, 2.0 * kPi);
  b.amplitude = approach(b.amplitude, 0.0, sp.amp_max / kWingFold, dt);
  b.tail_bend = approach(b.tail_bend, 0.0, sp.tail_rate, dt);
  b.tail_twist = approach(b.tail_twist, 0.0, sp.tail_rate, dt);
  b.sweep = approach(b.sweep, 0.0, sp.sweep_rate, dt);
  if (glm::length(b.position - b.via_point) < kSettledDistance &&
      glm::length(b.velocity) < kSettledSpeed && b.amplitude == 0.0 &&
      turn_angle(b.attitude, level) < kSettledAngle) {
    come_to_rest(b, b.via_point);
    b.landing_stage = LandingStage::none;
  }
}

// The ground is solid: a bird whose legs reach it on the way down stands, and stops where its
// legs can stop it from its speed over the ground (kSettleDecel).
// Touching down on its route's landing site, it has landed there: it runs out and stays (perched,
// as a bird on its branch; route.h: at_landing_site).
void touch_down(BirdState& b, const Species& sp, const World& w, double dt) {
  const dvec3 level = horizontal(b.velocity);
  const dvec3 run = b.position + level * (glm::length(level) / (2.0 * kSettleDecel));
  const dvec3 stop{run.x, w.ground_height + sp.stand_height, run.z};
  if (at_landing_site(b, sp, w, b.position)) {
    hold_on(b, FlightMode::perched, stop);
    ++b.targets_reached;
    return;
  }
  hold_on(b, FlightMode::standing, stop);
  b.rest_steps = whole_steps(kRestAfterTouchdown, dt);
}

// As a wingbeat begins (its phase passing 2 pi at `beat` Hz), the airspeed's rate over the beat
// that ended (speed_lead_error); on its legs none.
// A bird that hovers onto its branch (`hovers`): its path over the ground through the beat, and
// as a beat ends its mean speed over it (route.h: last_beat_speed).
void time_the_beat(BirdState& b, const World& w, double phase_before, double beat, bool on_legs,
                   bool hovers, double dt) {
  if (on_legs) {
    b.beat_airspeed = 0.0;
    b.airspeed_rate = 0.0;
    b.beat_path = 0.0;
    b.beat_speed = 0.0;
    return;
  }
  if (hovers) b.beat_path += glm::length(b.velocity) * dt;
  if (b.phase < phase_before) {
    const double airspeed = glm::length(b.velocity - wind_at(w, b.position.y));
    if (b.beat_airspeed > 0.0) b.airspeed_rate = (airspeed - b.beat_airspeed) * beat;
    b.beat_airspeed = airspeed;
    b.beat_speed = b.beat_path * beat;
    b.beat_path = 0.0;
  }
}

// One step of a bird that is not quarantined (step_bird).
void advance(BirdState& b, const Species& sp, const World& w, uint64_t step, double dt,
             StepForces* out, const Perception* seen) {
  // Settling after a grip or a touch-down; on the ground its rest runs meanwhile (the clock alone
  // ends it), and it takes off once rested and settled.
  if (b.landing_stage == LandingStage::settling) {
    settle(b, sp, w, dt);
    if (b.mode == FlightMode::standing && b.rest_steps > 0) --b.rest_steps;
    count_mode_step(b);
    return;
  }
  // At rest: perched, or standing until its rest is over (whole steps: exact after days) and it
  // faces into the wind, turning on its legs meanwhile.
  if (b.mode == FlightMode::perched) {
    count_mode_step(b);
    return;
  }
  if (b.mode == FlightMode::standing) {
    const bool into_wind = face_the_wind(b, sp, w, kSettleTurn * dt);
    if (b.rest_steps > 0 || !into_wind) {
      if (b.rest_steps > 0) --b.rest_steps;
      count_mode_step(b);
      return;
    }
    b.mode = FlightMode::taking_off;
    b.mode_steps = 0;
    b.frequency = sp.f_max;
    b.amplitude = sp.amp_max;
  }
  dvec3 goal = route_goal(b, sp, w);
  if (approach_branch(b, sp, w)) return;
  // A bird that sees its flock steers for its social goal, lookahead along u(d), at the airspeed
  // that goal commands (docs/MODEL.md "Flocking"); alone, it flies its route.
  double airspeed = b.airspeed;
  const bool social = seen && seen->neighbours > 0 && flocks_now(b);
  if (social) {
    goal = b.position + sp.lookahead * seen->direction;
    airspeed = seen->airspeed;
  }
  const Commands c = control(b, sp, w, dt, goal, airspeed, social);
  const StepForces f = forces(b, sp, w, dt, c, social ? seen : nullptr, step);

  // Euler integration (eqs. 6-8, 13, 14): position and attitude move with the rates at time t.
  const bool on_legs = b.mode == FlightMode::taking_off;
  // A bird of a flock with wakes, in the air: its wings' lift (their force across its flight
  // through the air) over about a wingbeat, what its wake carries (wake.h).
  if ((b.flocking & kFeelsWakes) && !on_legs) {
    const dvec3 air = b.velocity - wind_at(w, b.position.y);
    const dvec3 wing = f.wing[0] + f.wing[1] + f.wing[2] + f.wing[3];
    const double air2 = glm::dot(air, air);
    const dvec3 lift = air2 > 0.0 ? wing - air * (glm::dot(wing, air) / air2) : wing;
    b.lift += (glm::length(lift) - b.lift) * std::min(b.frequency * dt, 1.0);
  }
  b.position += b.velocity * dt;
  b.velocity += f.total / sp.mass * dt;
  b.attitude = integrate_attitude(b.attitude, c.omega, dt);
  b.omega = c.omega + angular_acceleration(box_inertia(sp), f.torque) * dt;
  if (on_legs) stand_on_legs(b, sp, w, dt);

  // The wingbeat, eqs. 4, 5 (wings at full power on the legs) and the tail, to t + dt.
  const double phase_before = b.phase, beat = beat_frequency(b, social ? seen : nullptr);
  b.phase = std::fmod(b.phase + 2.0 * kPi * beat * dt, 2.0 * kPi);
  time_the_beat(b, w, phase_before, beat, on_legs, hovers(sp), dt);
  if (c.final) {
    final_wingbeat(sp, c.energy_error, c.amplitude, c.hover, b.frequency, b.amplitude, dt);
  } else {
    b.frequency = on_legs ? sp.f_max : frequency_step(sp, b.frequency, c.energy_error, dt);
    b.amplitude = on_legs ? sp.amp_max : amplitude_step(sp, b.amplitude, c.energy_error, dt);
  }
  // The pitch trim integrates the energy balance.
  if (!on_legs)
    b.pitch_trim = std::clamp(b.pitch_trim + sp.balance_gain * c.balance / sp.trim_time * dt,
                              sp.pitch_min, sp.pitch_max);
  b.tail_bend = approach(b.tail_bend, c.bend, sp.tail_rate, dt);
  b.tail_twist = approach(b.tail_twist, c.twist, sp.tail_rate, dt);
  b.sweep = approach(b.sweep, c.sweep, sp.sweep_rate, dt);
  count_mode_step(b);
  if (c.circling)
    count_circling_step(b);
  else
    b.circling_steps = 0;
  if (on_legs && mode_time(b, dt) >= sp.crouch_time + sp.leg_time) {
    b.mode = FlightMode::flying;
    b.mode_steps = 0;
  }
  // The ground is solid: a bird in the air whose legs reach it on the way down touches down,
  // stands, and takes off again when it has rested (its route goes on).
  if (!on_legs && b.position.y < w.ground_height + sp.stand_height && b.velocity.y < 0.0) {
    touch_down(b, sp, w, dt);
  }
  if (out) *out = f;
}

}  // namespace

// A bird takes off into the wind: turned away from it, it would first fall back through it. Done
// once the turn left is within this step's: turn_towards then returns `into` itself (it judges by
// the turn's axis part; float attitudes cannot resolve a step's turn in w, turn_angle's).
bool face_the_wind(BirdState& b, const Species& sp, const World& w, double most) {
  const dvec3 wind = wind_at(w, b.position.y);
  if (!heeds_wind(sp, glm::length(horizontal(wind)))) return true;
  const glm::dquat into = facing(-wind);
  b.attitude = turn_towards(b.attitude, into, most);
  return b.attitude == into;
}

uint32_t whole_steps(double seconds, double dt) {
  const double steps = std::ceil(seconds / dt - 0.5);
  return steps <= 0.0 ? 0u : steps >= double(UINT32_MAX) ? UINT32_MAX : uint32_t(steps);
}

void step_bird(BirdState& b, const Species& sp, const World& w, uint64_t step, double dt,
               StepForces* out, const Perception* seen) {
  if (out) *out = StepForces{};
  if (b.mode == FlightMode::quarantined) return;
  const BirdState before = b;
  advance(b, sp, w, step, dt, out, seen);
  if (all_finite(b)) return;
  // NaN quarantine (issue 16): the step is undone and the bird frozen at its last finite state,
  // marked with the step's start; it is never stepped again, and its flock no longer sees it
  // (flocks_now). The compute shader does the same (step.glsl).
  b = before;
  b.mode = FlightMode::quarantined;
  b.quarantined_step = step;
  if (out) *out = StepForces{};
}

}  // namespace aeroflock
