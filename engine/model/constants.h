// Physical constants and the model's fixed numbers, for C++ (double) and GLSL (float): the
// compute shaders include this file too. CGS throughout (cm, g, s, dyn), radians inside.
#ifndef AEROFLOCK_MODEL_CONSTANTS_H
#define AEROFLOCK_MODEL_CONSTANTS_H

#ifdef __cplusplus
#include <cstdint>
#include <numbers>
#define AF_REAL(name, value) inline constexpr double name = value;
#define AF_COUNT(name, value) inline constexpr uint32_t name = value;
namespace aeroflock {
#else
#define AF_REAL(name, value) const float name = value;
#define AF_COUNT(name, value) const uint name = value;
#endif

AF_REAL(kAirDensity, 1.225e-3)  // rho, g/cm^3
AF_REAL(kGravity, 980.665)      // G, cm/s^2
// A target flown past within this many radii counts as passed (no endless orbits round it).
AF_REAL(kMissedTargetRadii, 3.0)
// The landing gate stands this many approach distances out on the branch's perpendicular. A bird
// whose track points away from the branch by more than acos(-kGateHeadingOut) (120 degrees) has
// not reached it.
AF_REAL(kGateApproaches, 5.0)
AF_REAL(kGateHeadingOut, 0.5)
// A bird whose heading is within asin(kLinedUpSine) (2 degrees) of the branch's perpendicular, or
// whose heading line crosses it farther than kFarthestCrossing times its distance to the branch,
// counts as lined up: it flies straight in. The crossing there is ill-conditioned (a float and a
// double computation of it differ by metres) and would bend the curve kilometres out.
AF_REAL(kLinedUpSine, 0.035)
AF_REAL(kFarthestCrossing, 4.0)
// Pitched this steeply (rad, up or down) a bird levels its wings (control.h: recovery_bank).
AF_REAL(kSteepPitch, 1.0471975511965976)
// Descending this steeply through the air (rad, 86 degrees) a bird levels its wings: banked, it is
// in a spiral dive, which pitching up only tightens (control.h: recovery_bank).
AF_REAL(kSteepDescent, 1.5)
// Faster through the air than this many times its max_speed a bird levels its wings: banked, a
// heavy eagle gliding down to a goal beneath it sped up to 28 m/s in a spiral dive, stalled nose
// high, and pitched past 60 degrees rolling out (control.h: recovery_bank).
AF_REAL(kDiveSpeed, 2.25)
// Slower through the air than kSpeedFirst min_speed, a bird's pitch holds its airspeed alone: the
// height's share of the balance grows from none there to whole at min_speed (control.h).
AF_REAL(kSpeedFirst, 0.75)
// Pitched up this far (rad, 10 degrees) past the most it commands (pitch_max, brake_pitch
// braking), its tail and sweep have lost to the wingbeat's own nose-up moment: the wingbeat rises
// no further (step.cpp). Pitched down as far past pitch_min, they have lost to the glide's
// nose-down moment: the wingbeat, whose downstroke lift the lead-lag carries forward, rises.
AF_REAL(kPitchOverrun, 0.17453292519943295)
// A bird turning at full bank flies a circle this many times wider than the coordinated turn's
// v^2 / (g tan bank_max): part of its weight hangs on the wingbeat's thrust, not the banked lift
// (an eagle at 10 m/s, banked 45 degrees: 15 m, not 10). Sizes the circle a goal inside is never
// reached from (control.h: circles_goal).
AF_REAL(kWideTurn, 1.5)
// A goal more than this far off the heading (rad, 120 degrees) is behind the bird (control.h:
// turn_on).
AF_REAL(kBehind, 2.0943951023931953)
// A goal less than this many times its horizontal distance above or below the bird is at about
// its height (control.h: circles_goal).
AF_REAL(kLevelGoal, 0.2)
// Circling a goal inside its full-bank circle for this share of a turn, a bird flies on with its
// wings level until it can turn onto it (step.cpp).
AF_REAL(kCirclingTurn, 0.25)
// The wake (wake.h): elliptic loading rolls the trailing vorticity up into two vortices pi / 4 of
// the span apart; their cores are kWakeCore of the span across.
AF_REAL(kWakeVortexSpan, 0.7853981633974483)
AF_REAL(kWakeCore, 0.05)
// A bird of a flock with wakes meets the wakes of at most kWakeSources of the birds it sees, the
// nearest ahead of it within kWakeReach spans (flock.cpp).
AF_COUNT(kWakeSources, 2)
AF_REAL(kWakeReach, 10.0)
// Formation flying (flock.cpp: formation): a bird predicts the upwash it would meet over
// kBeatSamples points of its wingbeat kFormationProbe spans to either side and above and below,
// and kPhaseProbe rad ahead and behind in its wingbeat; it seeks the best within kFormationReach
// spans and kPhaseReach rad, behind a bird at least kFormationBehind spans ahead of it.
AF_COUNT(kBeatSamples, 16)
AF_REAL(kFormationProbe, 0.1)
AF_REAL(kFormationReach, 0.5)
AF_REAL(kPhaseProbe, 0.7853981633974483)
// kPhaseProbe is this many of the kBeatSamples moments: the probes reuse the bird's wing places.
AF_COUNT(kPhaseProbeSamples, 2)
AF_REAL(kPhaseReach, 1.5707963267948966)
AF_REAL(kFormationBehind, 0.25)
// A bird in formation heads for its route's height too, the route's climb or descent at this
// many times the formation's weight (flock.cpp: social_goal): without it a loose group, nearly
// every bird following another, had none that held the route's height, and drifted 20-50 m above.
AF_REAL(kFormationRouteHeight, 2.0)
// BirdState::flocking: it sees its flock; and it meets the wakes of those it sees.
AF_COUNT(kSeesFlock, 1)
AF_COUNT(kFeelsWakes, 2)
// A braking bird aims this many perch radii above the perch: it sinks as it slows (step.cpp).
AF_REAL(kFlareAimAbove, 0.5)
// A braking bird sunk under its perch by kSunkPerchRadii perch radii and still sinking faster than
// kSunkTouchdowns touchdown_speed cannot climb back onto it: it goes round (route.h).
AF_REAL(kSunkPerchRadii, 0.25)
AF_REAL(kSunkTouchdowns, 1.5)
// A braking bird slower than this through the air (cm/s, horizontally) steers by where its head
// points, faster by its course through the air (control.h: steer_towards).
AF_REAL(kSteerAirspeed, 100.0)
// A landing bird plans to meet its branch at this fraction of touchdown_speed (control.h).
AF_REAL(kTouchdownAim, 0.5)
// A bird flares once it must brake at this share of its full flare to stop in time (route.h).
AF_REAL(kBrakeShare, 0.5)
// The hovering final (Species::hover_final, docs/MODEL.md "Take-off and landing"): braking begins
// kHoverBrakeDistances brake_distance out; the bird approaches kApproachAbove perch radii above the
// perch point, and braking it aims kApproachAbove radii above it from kFinalFrom radii out,
// falling smoothly to kEndAbove radii at kFinalTo radii (control.h: final_aim).
AF_REAL(kHoverBrakeDistances, 2.0)
AF_REAL(kApproachAbove, 0.25)
AF_REAL(kEndAbove, 0.03)
AF_REAL(kFinalFrom, 4.0)
AF_REAL(kFinalTo, 0.5)
// Its speed over the ground falls towards the point at kFinalDecel brake_decel to kFinalSpeed
// touchdown_speed there (control.h: final_speed); past the point it wants that speed back.
AF_REAL(kFinalDecel, 0.5)
AF_REAL(kFinalSpeed, 0.6)
// Its height: a climb of kFinalClimbGain (1/s) per cm below its aim, at most kFinalClimbMax (cm/s),
// a sink no faster than it can stop at kFinalSinkDecel (cm/s^2) by its aim; the wingbeat's error
// is the height that climb's error makes in kFinalLead (s). The amplitude answers it at once by
// kFinalAmplitudeGain per cm, about a part that integrates it at kFinalAmplitudeRate K_a within a
// band of kFinalBand perch radii; the frequency rises at kFinalFrequencyRate K_f hovering (and at
// full amplitude short of its climb, Species::final_beats_faster), else trims at kFinalTrimRate K_f
// to keep the amplitude kFinalTrimLow of its range above amp_min.
AF_REAL(kFinalClimbGain, 4.0)
AF_REAL(kFinalClimbMax, 100.0)
AF_REAL(kFinalSinkDecel, 50.0)
AF_REAL(kFinalLead, 0.25)
AF_REAL(kFinalAmplitudeGain, 0.03)
AF_REAL(kFinalAmplitudeRate, 2.0)
AF_REAL(kFinalBand, 0.1)
AF_REAL(kFinalFrequencyRate, 10.0)
AF_REAL(kFinalTrimRate, 2.0)
AF_REAL(kFinalTrimLow, 0.15)
// It hovers below kHoverAirspeed (cm/s, fully kHoverBand below it): the pitch at which the full
// wingbeat's force points up (trim.h: about atan(kHoverLift / (airspeed + kHoverLiftSpeed)),
// alike for the presets), at most kHoverBasePitch, plus kHoverPitchGain (rad per cm/s) of its
// speed along its head beyond the profile's, at most Species::hover_pitch_max; its pitch damping
// falls by kHoverDamping (the wingbeat swings the pitch rate within each beat); it banks up to
// kHoverBank steep as it is, and heads on within kHoldHeading perch radii of the point in calm air.
AF_REAL(kHoverAirspeed, 400.0)
AF_REAL(kHoverBand, 150.0)
AF_REAL(kHoverLift, 510.0)
AF_REAL(kHoverLiftSpeed, 86.0)
AF_REAL(kHoverBasePitch, 0.9599310885968813)
AF_REAL(kHoverPitchGain, 0.0026)
AF_REAL(kHoverDamping, 0.8)
AF_REAL(kHoverBank, 0.20943951023931956)
AF_REAL(kHoldHeading, 0.1)
// A species with hover_incidence brakes with its wings too: its arms' incidence, that much at the
// profile's speed, rises by kHoverIncidenceGain (rad per cm/s) of its speed beyond it, within [0,
// kHoverIncidenceMax] (the eagle's: docs/MODEL.md "The hovering final").
AF_REAL(kHoverIncidenceGain, 0.0031415926535897933)
AF_REAL(kHoverIncidenceMax, 0.6981317007977318)
// It grips where its feet meet the branch point: within kGripReach stand_height of the perch
// point, at a mean speed over the ground of at most touchdown_speed over its last wingbeat or
// kTouchdownWindow (s), whichever is longer (route.h: last_beat_speed).
AF_REAL(kGripReach, 0.4)
AF_REAL(kTouchdownWindow, 0.1)
// A bird that lands on the ground (Species::perches 0) comes in on a glide path this steep (rad)
// that ends on its site (route.h: route_goal), sinking at its speed over the ground times its
// tangent (1.2 m/s for the ibis, 1.4 for the goose at their slowest airspeeds in calm air).
AF_REAL(kGlideSlope, 0.10471975511965977)
// A bird that touches down on the ground stands this long (and until it has settled) before it
// takes off again, s.
AF_REAL(kRestAfterTouchdown, 0.5)
// Settling after a grip or a touch-down (step.h: settle): the legs pull the centre to where the
// bird sits as a critically damped spring of kSettleStiffness (1/s^2: it settles in about half a
// second), their pull at most kSettleDecel (cm/s^2, within the 30 m/s^2 a landing bird's speed may
// fall at, issue 40); the body turns level at no more than kSettleTurn (rad/s, 80 degrees/s, within
// 90). Settled: within kSettledDistance (cm) of it, slower than kSettledSpeed (cm/s), within
// kSettledAngle (rad) of level.
AF_REAL(kSettleStiffness, 144.0)
AF_REAL(kSettleDecel, 2500.0)
AF_REAL(kSettleTurn, 1.3962634015954636)
AF_REAL(kSettledDistance, 0.5)
AF_REAL(kSettledSpeed, 5.0)
AF_REAL(kSettledAngle, 0.001)
// Its wings fold from amp_max in this long, s (eq. 5's rate K_a, a quarter of amp_max a second for
// the presets, is the controller's, not the folding's).
AF_REAL(kWingFold, 0.25)
// The most neighbours a bird sees (a species' `neighbours`; the shaders' list is this long).
AF_COUNT(kMaxNeighbours, 16)
// How far birds' searches reached (flock.h: SearchReach): kReachBins half-octave bins of the
// distance in cm, the first from 2^(kReachFirstBin / 2) cm (32 cm), the last open above.
AF_COUNT(kReachBins, 24)
AF_COUNT(kReachFirstBin, 10)
// The device counts one perceiving bird in kReachSample (by index) in its histogram.
AF_COUNT(kReachSample, 16)
// Perception::seen_key's multiplier (Knuth's multiplicative hash), odd so that indices stay apart.
AF_COUNT(kSeenKeyFactor, 2654435761u)

#ifdef __cplusplus
inline constexpr double kPi = std::numbers::pi;
constexpr double radians(double degrees) { return degrees * (kPi / 180.0); }
constexpr double degrees(double radians) { return radians * (180.0 / kPi); }
}  // namespace aeroflock
#else
const float kPi = 3.14159265358979;
#endif
#undef AF_REAL
#undef AF_COUNT

#endif  // AEROFLOCK_MODEL_CONSTANTS_H
