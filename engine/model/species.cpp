#include "species.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "constants.h"

namespace aeroflock {
namespace {

// Parameters the paper uses but does not give (MODEL.md defaults), shared by both presets.
void set_common_defaults(Species& s) {
  s.A_arm = radians(40);
  s.A_hand = radians(20);
  s.lag_hand = radians(30);
  s.B_arm = radians(10);
  s.B_hand = radians(25);
  s.C_leadlag = radians(10);
  s.flap_bias = radians(10);
  s.twist_bias = radians(3);
  s.tail_incidence = radians(8);
  s.tail_rate = radians(100);
  s.tail_roll_max = radians(60);
  s.turn_rate = radians(45);
  s.dead_band = radians(3);
  s.heading_lead = 0.25;
  s.height_lead = 1.5;
  s.height_band = 100;
  s.bank_max = radians(45);
  s.steer_full_error = radians(45);
  s.roll_rate = radians(120);
  s.bank_time = 0.1;
  s.crouch_time = 0.1;
  s.push_angle = radians(45);
}

}  // namespace

Species eagle() {
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
  set_common_defaults(s);
  // Calibrated: the wings' mean pitching moment is ~0 at 8 deg body pitch at 10 m/s and does not
  // run away nose-up at full amplitude (lead-lag 7.5 deg).
  s.C_leadlag = radians(7.5);
  s.shoulder_x = -4;
  s.stand_height = 25;
  s.crouch_depth = 8;
  s.leg_force = 8.4e6;  // the starling's push scaled by mass
  s.leg_time = 0.1;
  s.approach_distance = 1200;
  s.brake_distance = 500;
  s.brake_pitch = radians(50);
  s.perch_radius = 200;
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
  set_common_defaults(s);
  s.shoulder_x = -3;  // the wings' mean pitching moment is ~0 at 8 deg body pitch at 10 m/s
  s.stand_height = 12;
  s.crouch_depth = 4;
  s.leg_force = 2.1e6;  // paper section 5
  s.leg_time = 0.1;
  s.approach_distance = 600;
  s.brake_distance = 250;
  s.brake_pitch = radians(50);
  s.perch_radius = 100;
  return s;
}

std::vector<Species> species_presets() { return {eagle(), starling()}; }

void validate(const Species& s) {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("species '" + s.name + "': " + what);
  };
  auto positive = [&](double v, const char* key) {
    if (!(v > 0) || !std::isfinite(v)) fail(std::string(key) + " must be > 0");
  };
  auto non_negative = [&](double v, const char* key) {
    if (!(v >= 0) || !std::isfinite(v)) fail(std::string(key) + " must be >= 0");
  };
  positive(s.wing_area, "wing_area");
  positive(s.mass, "mass");
  positive(s.f_min, "f_min");
  positive(s.f_max, "f_max");
  if (s.f_min > s.f_max) fail("f_min must be <= f_max");
  non_negative(s.K_f, "K_f");
  non_negative(s.amp_min, "amp_min");
  non_negative(s.amp_max, "amp_max");
  if (s.amp_min > s.amp_max) fail("amp_min must be <= amp_max");
  non_negative(s.K_a, "K_a");
  positive(s.box_a, "box_a");
  positive(s.box_b, "box_b");
  positive(s.box_c, "box_c");
  positive(s.tail_length, "tail_length");
  non_negative(s.bend_max, "bend_max");
  non_negative(s.rot_max, "rot_max");
  non_negative(s.tail_min, "tail_min");
  non_negative(s.Ct, "Ct");
  non_negative(s.ground_k, "ground_k");
  positive(s.wing_length, "wing_length");
  if (s.box_c < 2 * s.wing_length) fail("box_c (full span) must be >= 2 wing_length");
  if (!(s.arm_fraction > 0 && s.arm_fraction < 1)) fail("arm_fraction must be in (0, 1)");
  if (!(s.arm_area_fraction > 0 && s.arm_area_fraction < 1))
    fail("arm_area_fraction must be in (0, 1)");
  non_negative(s.Cd_0, "Cd_0");
  if (s.Cd_90 < s.Cd_0) fail("Cd_90 must be >= Cd_0");
  positive(s.tail_rate, "tail_rate");
  non_negative(s.tail_roll_max, "tail_roll_max");
  non_negative(s.turn_rate, "turn_rate");
  non_negative(s.dead_band, "dead_band");
  non_negative(s.heading_lead, "heading_lead");
  non_negative(s.height_lead, "height_lead");
  non_negative(s.height_band, "height_band");
  if (!(s.bank_max >= 0 && s.bank_max < kPi / 2)) fail("bank_max must be in [0, 90) degrees");
  positive(s.steer_full_error, "steer_full_error");
  positive(s.roll_rate, "roll_rate");
  positive(s.bank_time, "bank_time");
  non_negative(s.stand_height, "stand_height");
  non_negative(s.crouch_time, "crouch_time");
  non_negative(s.crouch_depth, "crouch_depth");
  non_negative(s.leg_force, "leg_force");
  non_negative(s.leg_time, "leg_time");
  non_negative(s.approach_distance, "approach_distance");
  non_negative(s.brake_distance, "brake_distance");
  positive(s.perch_radius, "perch_radius");
  if (s.perch_radius > s.brake_distance) fail("perch_radius must be <= brake_distance");
  auto angle_below_90 = [&](double v, const char* key) {
    if (!(std::fabs(v) < kPi / 2)) fail(std::string(key) + " must be within (-90, 90) degrees");
  };
  angle_below_90(s.tail_incidence, "tail_incidence");
  angle_below_90(s.brake_pitch, "brake_pitch");
  angle_below_90(s.push_angle, "push_angle");
}

Inertia box_inertia(const Species& s) {
  const double m = s.mass, a = s.box_a, b = s.box_b, c = s.box_c;
  return {m * (b * b + c * c) / 12.0, m * (c * c + a * a) / 12.0, m * (a * a + b * b) / 12.0};
}

}  // namespace aeroflock
