// Flight control through target spheres (paper 3.4, 4.1, 4.4): heading and elevation to a goal,
// height control (eqs. 4, 5), tail commands, bank, and the landing point P.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "species.h"
#include "world.h"

namespace aeroflock {

// sgn with a dead band: 0 while |x| <= band.
double sign_outside(double x, double band);

// heading_error, phi (Fig. 11): the horizontal angle from the head direction to the goal,
// target on the right > 0; in a wind, to where the head must point for the bird to fly over the
// ground towards the goal at `ground_speed` (crab_aim), or, flying faster through the air than
// that asks, or at an airspeed `commanded` otherwise (a scenario's), along the way to it at its
// airspeed (track_aim): it crabs. With `in_air` the way to the goal is itself the heading through
// the air (a flock's social goal, flock.h: route_heading). With `by_course` (braking)
// the angle is from its course through the air instead of its head (kSteerAirspeed).
// heading_error_ahead: the same, less the turn the bank is making (g tan(bank) / v) over
// heading_lead seconds; the tail twist steers by it, which damps the body's yaw. height_error: y_p
// - y_i of eqs. 4, 5, with the bird's height predicted height_lead seconds ahead so that the height
// control settles.
struct Steering {
  double heading_error;
  double heading_error_ahead;
  double height_error;
  double aim_speed;  // |crab_aim|, cm/s: the airspeed that makes ground_speed towards the goal
  double air_speed;  // cm/s, the bird's horizontal speed through the air (what a turn banks for)
};
Steering steer_towards(const Species& s, const glm::dquat& attitude, const glm::dvec3& position,
                       const glm::dvec3& velocity, const glm::dvec3& goal, const glm::dvec3& wind,
                       double ground_speed, bool by_course, bool commanded = false,
                       bool in_air = false);

// With the target well behind (more than kBehind off the heading), a bird banked more than half
// bank_max keeps turning the way it banks: either way round is about as long, and a goal passing
// beneath it (spiralled down to) would swing its bank from side to side as the goal's bearing
// crossed its tail. The heading errors are then measured that way round (beyond pi).
void turn_on(const Species& s, double bank, Steering& st);

// The horizontal air velocity that makes `ground_speed` over the ground towards the goal:
// ground_speed along the way to it, less the wind (0 at the goal).
glm::dvec3 crab_aim(const glm::dvec3& to_goal, const glm::dvec3& wind, double ground_speed);

// The horizontal air velocity of `airspeed` whose track over the ground runs along the way to
// the goal: it cancels the wind across the way and makes good what is left along it. A bird
// faster through the air than crab_aim asks (a tailwind, a crosswind) heads where this points;
// aiming by crab_aim it would point as far into the wind as the slower speed needs, and drift
// upwind. A wind across the way at or above `airspeed` cannot be cancelled: it heads straight
// into it. At the goal, or with no airspeed, crab_aim's.
glm::dvec3 track_aim(const glm::dvec3& to_goal, const glm::dvec3& wind, double airspeed);

// A bird that compensates for the wind's drift by `compensation` (drift_compensation: 0 none, 1
// in full) heads that share of the way from the goal's bearing to `aim` (the heading that holds
// its track): the crab angle times the compensation (Chapman et al. 2011). Either zero: `aim`.
glm::dvec3 compensated_aim(const glm::dvec3& to_goal, const glm::dvec3& aim, double compensation);

// The ground speed the bird makes towards its goal: cruise_speed, or on the way to a branch
// (`to_branch` cm from its perch, < 0: no branch ahead) no faster than it can brake to
// touchdown_speed at brake_decel by perch_radius.
double approach_speed(const Species& s, double to_branch);

// How hard the bird steers, in [-1, 1]: 0 inside the dead band, then in proportion to the
// heading error, fully from steer_full_error on. Scales the tail twist and the bank.
double steer_share(const Species& s, double heading_error);

// eq. 4 and eq. 5: frequency and amplitude move at K_f, K_a towards more lift when the goal is
// above (dy > 0), less when below, and stay within [min, max]. The controller passes the total
// energy error as dy, so that a bird too slow for its command beats harder too.
double frequency_step(const Species& s, double frequency, double dy, double dt);
double amplitude_step(const Species& s, double amplitude, double dy, double dt);

// The tail's commanded twist (4.1; the bend is the elevator's): the goal on the right rolls it
// right side down, towards the turn. The air, meeting the body from below, then presses on the
// tail's upper surface and pushes it left: the nose turns right (docs/MODEL.md: pushing the tail
// left turns the nose right). With fixed-rate turning (eq. 3 turns the body) the twist follows
// heading_error instead.
double tail_twist_command(const Species& s, const Steering& steering, bool fixed_rate);

// Moves `angle` towards `command` by at most rate dt.
double approach(double angle, double command, double rate, double dt);

// Tail model: the bank that turns the heading at heading_error / turn_time (however far the goal
// is), or tighter onto the pure-pursuit circle through a near goal (curvature 2 sin(phi) /
// distance), at most bank_max; bank_max with the goal behind, 0 inside the dead band (`dead_band`:
// the species', or 0 hovering onto the branch point).
double heading_bank(const Species& s, double heading_error, double distance, double speed,
                    double dead_band);

// The radius of the circle a bird flies at full bank: kWideTurn times v^2 / (g tan bank_max).
double full_bank_radius(const Species& s, double speed);

// Whether a goal `distance` away (horizontally) and `rise` above lies inside a circle of `radius`
// tangent to the heading (the one the bird flies at full bank, full_bank_radius) and at about its
// height (|rise| < kLevelGoal distance), in air calm enough (`wind`, horizontal, slower than
// speed / 2 pi) that the circle does not drift over it: turning, the bird would circle it for
// ever. A goal far above or below is spiralled to.
bool circles_goal(double heading_error, double distance, double radius, double speed, double rise,
                  double wind);

// The largest bank at `pitch`, `descent` (the flight path's angle below the horizontal through
// the air, rad, >= 0) and `airspeed`: bank_max up to kSteepPitch / 2 of pitch, kSteepDescent / 2
// of descent and kDiveSpeed - 0.5 times max_speed, none from the steep angles or kDiveSpeed times
// max_speed on. A bird pitched steeply up or down, descending steeply or diving fast levels its
// wings first, so that a banked dive or climb does not tighten into a spiral.
double recovery_bank(const Species& s, double pitch, double descent, double airspeed);

// The flight path's angle below the horizontal through the air (rad, 0 when climbing or level),
// from the air velocity's vertical part and its length (the airspeed).
double descent_angle(double air_climb, double airspeed);

// The largest bank `height` (cm, body above the ground) allows: the wingtip stays above it.
double ground_bank(const Species& s, double height);

// The bank that makes lift supply the centripetal force of a turn at `turn_rate` (rad/s, to the
// right > 0) and `speed`, at most bank_max: the bird banks into the turn to avoid skidding (3.4).
double coordinated_bank(const Species& s, double turn_rate, double speed);

// Airspeed, pitch and sweep (beyond the paper; docs/MODEL.md "Attitude, airspeed and height").
// The airspeed the bird flies: its command within [min_speed, max_speed]; without one (<= 0),
// the crab aim's (`aim_speed`, Steering's) within [cruise_speed, max_speed]. Once its branch is
// the goal (`to_branch`) the crab aim's within [min_speed, max_speed], whatever its command: it
// slows for the branch as approach_speed asks, and lands into the wind.
double commanded_airspeed(const Species& s, double command, double aim_speed, bool to_branch);

// The energy errors, cm: `total` (height error plus the airspeed's kinetic-energy deficit over
// g) feeds the wingbeat (eqs. 4, 5); `balance` (height error within balance_band less the same
// deficit) is what the pitch corrects: > 0, too little height for the speed it has. Below
// min_speed the height's share of the balance shrinks, to none at kSpeedFirst min_speed: a slow
// bird lowers its nose for speed first, whatever its height error, as it would near the stall.
struct Energy {
  double total, balance;
};
// `height` and `goal_height` are above where it would stand. Below its goal, the height it lowers
// its nose to trade for speed is at most what it has above clearance_floor: a slow bird near the
// ground that has to climb beats its wings for speed rather than dive for it.
Energy energy_errors(const Species& s, double height_error, double airspeed, double commanded,
                     double height, double goal_height);
// The height below which a bird climbs out (commanded_pitch) and trades no height for speed
// (energy_errors): clearance, or its goal's height if lower.
double clearance_floor(const Species& s, double goal_height);

// How far (cm) a bird sinking through the air at `air_climb` < 0 (cm/s) still sinks while its
// wingbeat rises from `amplitude` to amp_max at K_a (eq. 5): half the time that takes, the
// amplitude rising evenly. The wingbeat's energy error counts it, so that a gliding bird starts
// beating before it reaches its goal's height, not on it (a heavy eagle gliding down onto a target
// sank 19 m under it while its amplitude rose from 0 over 4 s). 0 climbing or level.
double spool_lead(const Species& s, double amplitude, double air_climb);

// How far (cm) the airspeed's rate over the last wingbeat (`airspeed_rate`, cm/s^2) will have
// moved the energy in speed_lead: the wingbeat's energy error of a bird flying on its flock's
// commands counts it, so that eqs. 4, 5 ease off as the speed comes back rather than when it is
// back, and stop ringing (docs/MODEL.md "Holding its place"). A bird alone flies them as the paper
// has them.
double speed_lead_error(const Species& s, double airspeed, double airspeed_rate);

// The pitch the bird holds: its integral trim plus balance_gain times the balance, within
// [pitch_min, pitch_max]; `height` (cm above the ground) below the clearance, and the goal not
// lower, no less than climb_pitch in proportion to how far below.
double commanded_pitch(const Species& s, double pitch_trim, double balance, double height,
                       double goal_height);

// Whether a bird heeds a wind of `speed` (cm/s) when it lands or takes off: it lands and takes off
// into one faster than kTouchdownAim touchdown_speed (downwind, it could not slow to grip).
bool heeds_wind(const Species& s, double speed);

// The airspeed at which a bird makes kTouchdownAim touchdown_speed over the ground towards its
// perch (`to_perch` away) in the wind: what it brakes to.
double perch_airspeed(const Species& s, const glm::dvec3& to_perch, const glm::dvec3& wind);
// Braking for the branch (the flare): how hard, in [0, 1]: the deceleration through the air that
// slows the bird from `airspeed` to `to_airspeed` (perch_airspeed) by half perch_radius from its
// perch
// (`to_perch` cm away), over flare_decel.
double flare_share(const Species& s, double airspeed, double to_airspeed, double to_perch);
// The flare's pitch: from the pitch trim towards brake_pitch by the share; within
// [pitch_min, brake_pitch].
double flare_pitch(const Species& s, double pitch_trim, double share);

// The hovering final (Species::hover_final; constants.h has its numbers). Whether the species
// lands so.
bool hovers(const Species& s);
// How far above the perch point it aims braking, `to_point` (cm) from it horizontally: a smoothstep
// from kApproachAbove perch radii at kFinalFrom radii to kEndAbove radii at kFinalTo radii.
double final_aim(const Species& s, double to_point);
// Where it aims across its way to the point (cm, horizontal, added to the point): against its drift
// across that way, by where the drift takes it in final_track_lead (or before it arrives); none
// within kHoldHeading perch radii, fading in over as many again.
glm::dvec3 final_track(const Species& s, const glm::dvec3& way, const glm::dvec3& velocity);
// How fast that aim moves up (cm/s, < 0 as it falls) for a bird flying at `velocity`, `way` from
// the point.
double final_aim_rate(const Species& s, const glm::dvec3& way, const glm::dvec3& velocity);
// The speed over the ground it brakes to (cm/s), `to_perch` from the perch and `to_point` from the
// point horizontally: approach_speed's, or less, falling at kFinalDecel brake_decel to kFinalSpeed
// touchdown_speed at the point.
double final_speed(const Species& s, double to_perch, double to_point);
// The climb it commands (cm/s) `height_error` (cm) below its aim, which moves at `aim_rate`.
double final_climb(double height_error, double aim_rate);
// How much it hovers, in [0, 1], at `airspeed` (cm/s, over its last wingbeat): 1 below
// kHoverAirspeed - kHoverBand, 0 above kHoverAirspeed.
double hover_share(double airspeed);
// Its pitch hovering at `airspeed` (cm/s), its speed along its head over the ground `along` where
// the profile wants `wanted`: the pitch at which the full wingbeat's force points up, at most
// kHoverBasePitch, plus kHoverPitchGain per cm/s too fast, within [0, hover_pitch_max].
double hover_pitch(const Species& s, double airspeed, double along, double wanted);
// Its arms' added incidence hovering so (Species::hover_incidence; 0 without it): the species'
// plus kHoverIncidenceGain per cm/s too fast, within [0, kHoverIncidenceMax].
double hover_incidence(const Species& s, double along, double wanted);
// Its wingbeat amplitude this step: its amplitude now and kFinalAmplitudeGain of the wingbeat's
// error (cm), within the species' range.
double final_amplitude(const Species& s, double amplitude, double energy_error);
// Its wingbeat after a step `dt`: the amplitude's integral part follows the error (cm) at
// kFinalAmplitudeRate K_a within kFinalBand perch radii; the frequency rises at
// kFinalFrequencyRate K_f hovering (share > 0.5) or, with final_beats_faster, at full amplitude
// short of its climb; else trims the amplitude used (`used`) towards kFinalTrimLow of its range at
// kFinalTrimRate K_f.
void final_wingbeat(const Species& s, double energy_error, double used, double hover,
                    double& frequency, double& amplitude, double dt);
// The lowest pitch it commands going round from a hover at `airspeed` (cm/s): brake_pitch at
// rest, falling to none (-pi) at half min_speed, so that it beats on to speed up nose high rather
// than fall through nose down.
double go_round_pitch(const Species& s, double airspeed);

// The tail bend (the elevator) and the sweep that hold `pitch_command`, from the pitch error
// less pitch_damping times the pitch rate: the sweep sweep_gain times it (within sweep_max), the
// tail pitch_gain times what exceeds pitch_band (within bend_max), so that in steady flight the
// tail stays closed.
struct PitchControl {
  double bend, sweep;
};
PitchControl pitch_control(const Species& s, double pitch_command, double pitch, double pitch_rate);

// How fast the body's pitch and bank angles change with body rates `omega` (rad/s).
double pitch_rate(const glm::dquat& attitude, const glm::dvec3& omega);
double bank_rate(const glm::dquat& attitude, const glm::dvec3& omega);

// The body roll rate omega.x that turns the bank towards `bank_command` with time constant
// bank_time (at most roll_rate), allowing for the bank the other two body rates make.
double roll_for_bank(const Species& s, const glm::dquat& attitude, const glm::dvec3& omega,
                     double bank_command);

// Landing path control (paper 4.4, Fig. 14): Q1 the bird, Q2 the branch point, Q3 where the line
// from Q1 along the bird's horizontal heading meets the horizontal line from Q2 perpendicular to
// the branch (at the branch's height). P = 0.25 Q1 + 0.5 Q3 + 0.25 Q2, the middle of the
// quadratic Bezier curve Q1 Q3 Q2. Without an intersection ahead of the bird, or lined up with the
// perpendicular (constants.h: kLinedUpSine, kFarthestCrossing), P = Q2: straight in.
glm::dvec3 landing_point(const glm::dvec3& bird, const glm::dvec3& heading,
                         const glm::dvec3& branch_point, const glm::dvec3& branch_direction);

// The landing curve: the quadratic Bezier Q1 Q3 Q2 whose middle is P, at u in [0, 1].
glm::dvec3 landing_curve(const glm::dvec3& q1, const glm::dvec3& p, const glm::dvec3& q2, double u);

// Pure pursuit along the landing curve: from `u`, the parameter of the first curve point ahead of
// the bird (not behind it along the curve) at least `lookahead` away; 1 at the branch.
double landing_progress(const glm::dvec3& q1, const glm::dvec3& p, const glm::dvec3& q2, double u,
                        const glm::dvec3& position, double lookahead);

}  // namespace aeroflock
