#include "species.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "constants.h"

namespace aeroflock {

namespace {

// The eagle's body and controller with the flaring final it was calibrated with: the ibis and the
// goose, which land on the ground, are built on it.
Species flaring_eagle() {
  Species s;
  s.name = "eagle";
  s.wing_area = 7200;
  s.mass = 2000;
  s.f_min = 2;
  s.f_max = 5;
  s.K_f = 0.36;
  s.amp_min = 0.0;
  s.amp_max = 1.0;
  s.K_a = 0.25;
  s.box_a = 80;
  s.box_b = 20;
  s.box_c = 220;
  s.tail_length = 40;
  s.bend_max = radians(10);
  s.rot_max = radians(45);
  s.tail_min = radians(10);
  s.Ct = 1.78;
  s.ground_k = 10;
  s.wing_length = 90;
  // Calibrated: the wings' mean pitching moment is ~0 at 8 deg body pitch at 10 m/s and does not
  // run away nose-up at full amplitude (lead-lag 7.5 deg).
  s.C_leadlag = radians(7.5);
  s.shoulder_x = -4;
  // Its pitch runs past 60 deg in steep banked climbs at pitch_max 35 deg, and in dives at
  // pitch_min -30 deg (the nose drops on through full nose-up tail and sweep as it rolls level).
  s.pitch_max = radians(25);
  s.pitch_min = radians(-25);
  // Its pitch, slow to answer (the body's inertia), hunts at low airspeed with the starling's
  // sweep gain: the tail bend does more of the work.
  s.sweep_gain = 0.5;
  s.pitch_gain = 1.5;
  s.min_speed = 800;  // the airspeeds it holds level (7 and 14 m/s: it sinks)
  s.max_speed = 1300;
  s.stand_height = 25;
  s.crouch_depth = 8;
  s.leg_force = 8.4e6;  // the starling's push scaled by mass
  s.leg_time = 0.1;
  s.approach_distance = 1200;
  s.brake_distance = 800;
  // At 45 deg a heavy eagle (mass +30 %) flared on past 60 deg pitch in 2 of 48 landings.
  s.brake_pitch = radians(38);
  s.perch_radius = 200;
  s.separation_radius = 836;  // 3.8 wingspans, as the starling's
  return s;
}

}  // namespace

Species eagle() {
  Species s = flaring_eagle();
  // It hovers onto the branch point (issue 40), braking with its wings as well as its pitch: its
  // pitch is slow to answer, and pitched at the 40-50 degrees it holds its full wingbeat drives it
  // on at 3-4 m/s (trim.h: the force points up only at 87 degrees at rest, at 50 with 20 degrees
  // more incidence). Pitched at up to 65 degrees it overshot to 85; at the default 15 degrees of
  // flare incidence it porpoised in an 8 m/s headwind and sank under the branch.
  s.hover_final = 1;
  s.hover_incidence = radians(5);
  s.hover_pitch_max = radians(50);
  s.brake_incidence = radians(26);
  return s;
}

Species starling() {
  Species s;
  s.name = "starling";
  s.wing_area = 1760;
  s.mass = 500;
  s.f_min = 8;
  s.f_max = 10;
  s.K_f = 1.0;
  s.amp_min = 0.6;
  s.amp_max = 1.0;
  s.K_a = 0.25;
  s.box_a = 40;
  s.box_b = 10;
  s.box_c = 100;
  s.tail_length = 20;
  s.bend_max = radians(10);
  s.rot_max = radians(60);
  s.tail_min = radians(10);
  s.Ct = 1.78;
  s.ground_k = 10;
  s.wing_length = 40;
  s.shoulder_x = -3;  // the wings' mean pitching moment is ~0 at 8 deg body pitch at 10 m/s
  // Its wings beat at 8-10 Hz, their lead-lag swinging at up to 630 deg/s: its sweep moves as
  // quickly. At 200 deg/s (the eagle's) a stalled starling's pitch swung by 60-85 deg either way,
  // the sweep lagging from limit to limit (0.3 s a cycle).
  s.sweep_rate = radians(500);
  s.stand_height = 12;
  s.crouch_depth = 4;
  s.leg_force = 2.1e6;  // paper section 5
  s.leg_time = 0.1;
  s.approach_distance = 600;
  s.brake_distance = 400;
  s.brake_pitch = radians(45);
  s.perch_radius = 100;
  s.hover_final = 1;  // it hovers onto the branch point (issue 40)
  return s;
}

Species ibis() {
  // Beyond the paper: the northern bald ibis (Geronticus eremita) of Portugal et al. 2014's V
  // formations, from published morphometrics (docs/MODEL.md "The presets" gives the sources),
  // with the eagle's controller; what differs from it was calibrated on the envelope.
  Species s = flaring_eagle();
  s.name = "ibis";
  s.mass = 1300;       // adults 1.0-1.5 kg
  s.box_c = 130;       // wingspan 125-135 cm
  s.wing_area = 2250;  // the span at aspect ratio 7.5 (no measured area found)
  s.wing_length = 58;
  s.box_a = 60;  // body with neck and bill: the eagle's pitch inertia per mass
  s.box_b = 12;
  s.tail_length = 30;
  s.cruise_speed = 1400;  // 14 m/s, the migrating flock's
  s.min_speed = 1100;
  s.max_speed = 1800;
  // It beats at 4.0 Hz in the field; the model's wing, twice the paper's birds' wing loading,
  // needs a deeper stroke and 5.3 Hz to cruise at 14 m/s, and up to 7 Hz to climb away.
  s.f_min = 3.5;
  s.f_max = 7;
  s.A_arm = radians(80);
  s.A_hand = radians(35);
  // At the eagle's 7.5 deg the deeper stroke pitched the body 60 deg in the beat of a climb.
  s.C_leadlag = radians(5);
  s.twist_bias = radians(8);  // trimmed at 5-11 deg of pitch at 14 m/s
  s.stand_height = 25;
  s.crouch_depth = 8;
  s.leg_force = 5.5e6;  // the eagle's push scaled by mass
  s.perches = 0;        // it lands on the ground
  s.perch_radius = 800;
  s.approach_distance = 2500;
  // Formation flying (docs/MODEL.md): a follower keeps 1.2 spans from the bird it follows, its
  // airspeed steadied by the wingbeat's lead and its place by small turns (the paper's 3 degree
  // dead band left its corrections of 1-2 degrees unsteered).
  s.w_formation = 8;
  s.speed_lead = 1.0;
  s.dead_band = radians(0.3);
  s.separation_radius = 156;
  s.w_separation = 2;
  return s;
}

Species goose() {
  // Beyond the paper: the greylag goose (Anser anser), whose skeins fly in V and echelon, from
  // published morphometrics (docs/MODEL.md "The presets"), with the eagle's controller; what
  // differs from it was calibrated on the envelope.
  Species s = flaring_eagle();
  s.name = "goose";
  s.mass = 3300;       // males 3.5 kg, females 3.1 kg
  s.box_c = 160;       // wingspan 149-168 cm
  s.wing_area = 2840;  // the span at aspect ratio 9 (no measured area found): 114 N/m2
  s.wing_length = 70;
  s.box_a = 75;  // body with neck and bill
  s.box_b = 15;
  s.tail_length = 15;
  s.cruise_speed = 1750;  // migrating geese fly at 17-19 m/s
  s.min_speed = 1300;
  s.max_speed = 2200;
  // About 4 Hz in the field; the model's wing, four times the paper's birds' wing loading, needs
  // 6.6 Hz to cruise at 17.5 m/s and up to 9 Hz to climb away.
  s.f_min = 3.5;
  s.f_max = 9;
  s.A_arm = radians(70);
  s.A_hand = radians(35);
  s.C_leadlag = radians(5);
  s.shoulder_x = -6;
  s.twist_bias = radians(11);
  // Its turning circle is 1.75 times the eagle's at cruise: at 1 s two turns back to a target 50 m
  // behind, from 5 m/s, came round too late.
  s.turn_time = 0.8;
  // Its pitch swings 11 degrees within a beat at cruise: at 3 degrees its short tail bent open for
  // 70 % of a straight cruise.
  s.pitch_band = radians(4);
  s.stand_height = 35;
  s.crouch_depth = 10;
  // 6 times its weight: at the eagle's 4.3 times one take-off in 24 (across a 5 m/s wind to a
  // target 10 m up, 90 degrees off) climbed away too late.
  s.leg_force = 2.0e7;
  s.perches = 0;  // it lands on the ground
  s.perch_radius = 1500;
  s.approach_distance = 3000;
  // Formation flying (docs/MODEL.md): a follower keeps 1.2 spans from the bird it follows, as the
  // ibis does.
  s.w_formation = 8;
  s.speed_lead = 1.0;
  s.dead_band = radians(0.3);
  s.separation_radius = 192;
  s.w_separation = 2;
  return s;
}

Species european_starling() {
  // Beyond the paper: the real European starling (Sturnus vulgaris) of the field's murmurations
  // (Ballerini et al. 2008), from published morphometrics (docs/MODEL.md "The presets" gives the
  // sources), with the paper starling's controller; what differs from it was calibrated on the
  // envelope. The paper's `starling` is six times heavier and 2.6 times wider.
  Species s = starling();
  s.name = "european_starling";
  // It hovers onto the branch point as the paper starling does; its grip's reach (2 cm) is 0.4 of
  // the paper starling's: it steers against its drift across its way in (at 0.6 s of lead; without,
  // 12 cm wide of the point in calm air from 45-135 degrees off), and at full amplitude still short
  // of its climb it beats faster (without, 4 of its 48 landings went round for good).
  s.hover_final = 1;
  s.final_track_lead = 0.6;
  s.final_beats_faster = 1;
  s.mass = 80;        // 75-90 g
  s.box_c = 39;       // wingspan 37-42 cm
  s.wing_area = 217;  // the span at aspect ratio 7 (no measured area found): 36 N/m2
  // The paper starling's wing, tail and legs scaled by the span (0.39) and the mass (0.16); the
  // body box as long as the bird with its bill (19-23 cm): at 16 cm its pitch swung 26 degrees
  // within a beat.
  s.wing_length = 16;
  s.box_a = 20;
  s.box_b = 5;
  s.tail_length = 8;
  s.shoulder_x = -1.6;  // its tail closed for a third of a straight cruise (at -3 cm, never)
  s.stand_height = 5;
  s.crouch_depth = 1.6;
  s.leg_force = 3.4e5;
  s.perch_radius = 40;    // one wingspan, as the paper starling's
  s.cruise_speed = 1100;  // the field's flocks: 6.9-15.2 m/s, mean 10.6
  s.min_speed = 700;
  s.max_speed = 1500;
  // 10-14 Hz in the wind tunnel; the model's wing needs a deeper stroke and 14-15 Hz to cruise at
  // 11 m/s, and up to 19 Hz to climb away and to slow onto a branch.
  s.f_min = 11;
  s.f_max = 19;
  s.A_arm = radians(80);
  s.A_hand = radians(35);
  s.twist_bias = radians(10);
  // At the paper starling's 0.25/s the energy loop hunted (amplitude 0.61-0.99 every 2.2
  // s, 9.7-12.1 m/s): its deeper stroke moves more force per unit of amplitude.
  s.K_a = 0.15;
  // At the paper starling's 15 degrees a calm landing arrived at 5 m/s and went round for ever;
  // at its 45 degrees of flare, pitched past 60. Its calm landings go round (docs/MODEL.md).
  s.brake_incidence = radians(30);
  s.brake_pitch = radians(35);
  // Its flock (docs/FIELD.md): the paper starling's perception in its own wingspans (20); a
  // separation zone of 3.7 wingspans, 1.75 times longer along its flight, puts its first neighbours
  // at its sides as the field's (at 3.8 wingspans and round: gamma(1) 0.27, r1 0.90 m). Its zone
  // is small for its speed: judged where each neighbour will be nearest over 0.75 s, not where it
  // is, a bird closing at 1-5 m/s steps aside in time (judged where they are, with a zone of 4.1
  // wingspans: 0.8-1.0 % of the birds nearer than half a wingspan in the worst frame; 0.4 %).
  s.separation_radius = 145;
  s.separation_front = 1.75;
  s.separation_lookahead = 0.75;
  s.perception_radius = 800;
  return s;
}

std::vector<Species> species_presets() {
  return {eagle(), starling(), ibis(), goose(), european_starling()};
}

void validate(const Species& s) {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("species '" + s.name + "': " + what);
  };
  // `max` in the file's `unit` (species.def); the message gives it so, e.g. "<= 180 degrees".
  auto check = [&](double v, Rule rule, const char* key, double max, Unit unit) {
    const std::string k = key;
    switch (rule) {
      case Rule::positive:
        if (!(v > 0) || !std::isfinite(v)) fail(k + " must be > 0");
        break;
      case Rule::non_negative:
        if (!(v >= 0) || !std::isfinite(v)) fail(k + " must be >= 0");
        break;
      case Rule::fraction:
        if (!(v > 0 && v < 1)) fail(k + " must be in (0, 1)");
        break;
      case Rule::within_90:
        if (!(std::fabs(v) < kPi / 2)) fail(k + " must be within (-90, 90) degrees");
        break;
      case Rule::bank:
        if (!(v >= 0 && v < kPi / 2)) fail(k + " must be in [0, 90) degrees");
        break;
      case Rule::any:
        if (!std::isfinite(v)) fail(k + " must be a finite number");
        break;
    }
    if (!(std::fabs(v) <= from_unit(max, unit))) {
      std::ostringstream bound;
      bound << max
            << (unit == Unit::degrees              ? " degrees"
                : unit == Unit::degrees_per_second ? " deg/s"
                                                   : "");
      fail(k + (rule == Rule::any ? " must be within +-" : " must be <= ") + bound.str());
    }
  };
#define AF_SPECIES_PARAM(param, default_value, unit, rule, max) \
  check(s.param, Rule::rule, #param, max, Unit::unit);
#include "species.def"
#undef AF_SPECIES_PARAM
  // Between parameters.
  if (s.f_min > s.f_max) fail("f_min must be <= f_max");
  if (s.amp_min > s.amp_max) fail("amp_min must be <= amp_max");
  if (s.box_c < 2 * s.wing_length) fail("box_c (full span) must be >= 2 wing_length");
  if (s.Cd_90 < s.Cd_0) fail("Cd_90 must be >= Cd_0");
  // A bird that lands on the ground does not brake: its perch_radius is its site's (route.h).
  if (s.perches != 0.0 && s.perch_radius > s.brake_distance)
    fail("perch_radius must be <= brake_distance");
  if (!(s.min_speed <= s.cruise_speed && s.cruise_speed <= s.max_speed))
    fail("min_speed <= cruise_speed <= max_speed must hold");
  if (s.pitch_min >= s.pitch_max) fail("pitch_min must be < pitch_max");
  // Shorter along the flight than across, the zone would leave a neighbour straight ahead neither
  // separation nor cohesion (flock.h: zone_distance).
  if (s.separation_front < 1.0) fail("separation_front must be >= 1");
  if (s.perches != 0.0 && s.perches != 1.0) fail("perches must be 0 (ground) or 1 (branches)");
  if (s.separation_all_round != 0.0 && s.separation_all_round != 1.0)
    fail("separation_all_round must be 0 (its k nearest from those it sees) or 1 (all round)");
  if (s.neighbours != std::floor(s.neighbours) || s.neighbours > kMaxNeighbours)
    fail("neighbours must be a whole number <= " + std::to_string(kMaxNeighbours));
  if (!(s.blind_angle < 2.0 * kPi)) fail("blind_angle must be < 360 degrees");
}

Inertia box_inertia(const Species& s) {
  const double m = s.mass, a = s.box_a, b = s.box_b, c = s.box_c;
  return {m * (b * b + c * c) / 12.0, m * (c * c + a * a) / 12.0, m * (a * a + b * b) / 12.0};
}

}  // namespace aeroflock
