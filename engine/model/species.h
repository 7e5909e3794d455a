// A species: Table 1 of the paper plus the parameters MODEL.md adds (kinematics, coefficient
// curves, control and take-off/landing constants). Angles in radians, lengths in cm.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace aeroflock {

struct Species {
  std::string name;

  // Table 1.
  double wing_area = 0;    // S, both wings, cm^2
  double mass = 0;         // m, g
  double f_min = 0, f_max = 0;       // wingbeat frequency bounds, Hz
  double K_f = 0;                    // frequency rate, Hz/s (eq. 4)
  double amp_min = 0, amp_max = 0;   // wingbeat amplitude bounds (fraction of the stroke)
  double K_a = 0;                    // amplitude rate, 1/s (eq. 5)
  double box_a = 0, box_b = 0, box_c = 0;  // body box edges along x, y, z, cm (eq. 12)
  double tail_length = 0;  // lr, cm (eq. 9)
  double bend_max = 0;     // largest tail bend, rad
  double rot_max = 0;      // largest tail twist, rad
  double tail_min = 0;     // phi_min, tail opening when closed, rad (eq. 10)
  double Ct = 0;           // tail opening gain (eq. 10)
  double ground_k = 0;     // ground effect coefficient k, cm (eq. 15)
  double wing_length = 0;  // l, one wing shoulder to tip, cm

  // Wingbeat kinematics (MODEL.md, replaces Fig. 6), radians.
  double A_arm = 0, A_hand = 0;  // flapping amplitudes at amp = 1
  double lag_hand = 0;           // phase lag of the hand behind the arm
  double B_arm = 0, B_hand = 0;  // feathering amplitudes
  double C_leadlag = 0;          // lead-lag amplitude
  double flap_bias = 0;          // mean flapping angle of the arm
  double twist_bias = 0;         // the arm's mean incidence (leading edge UP > 0)
  double shoulder_x = 0;            // shoulders ahead of the centre of mass (< 0: behind), cm
  double arm_fraction = 0.45;       // arm length / l
  double arm_area_fraction = 0.5;   // arm area / area of one wing

  // Coefficient curves (MODEL.md, replaces Fig. 8):
  // Cl = Cl_max sin(2 alpha), Cd = Cd_0 + (Cd_90 - Cd_0) sin^2(alpha).
  double Cl_max = 1.2, Cd_0 = 0.05, Cd_90 = 1.95;

  // Tail geometry: hinge at x = -a/2; the closed tail plane sits at tail_incidence (trailing edge
  // up > 0) from the body x axis; the tail force acts at 2/3 lr behind the hinge.
  double tail_incidence = 0;  // sets the body's trimmed pitch relative to the air
  double tail_roll_max = 0;  // largest roll of the tail plane from level, bank plus twist, rad
  double tail_rate = 0;  // how fast the tail moves towards its commanded bend and twist, rad/s

  // Steering (paper 3.4 and MODEL.md defaults).
  double turn_rate = 0;        // R, standard rotation velocity (fixed-rate turning), rad/s
  double dead_band = 0;        // heading dead band, rad
  double heading_lead = 0;     // heading control looks this far ahead along the banked turn, s
  double height_lead = 0;      // height control looks this far ahead: y + height_lead vy, s
  double height_band = 0;      // the tail bends only while the height error exceeds it, cm
  double bank_max = 0;         // largest bank, rad
  double steer_full_error = 0;  // heading error at which the bird steers fully (tail twist, bank), rad
  double roll_rate = 0;        // largest bank (and braking pitch) rate, rad/s
  double bank_time = 0;        // time constant of the bank (and braking pitch) control, s

  // Take-off (paper 4.3) and landing (4.4).
  double stand_height = 0;   // height of the body centre above the ground when standing, cm
  double crouch_time = 0;    // s
  double crouch_depth = 0;   // cm the body sinks while crouching
  double leg_force = 0;      // dyn (0: no leg push)
  double leg_time = 0;       // s
  double push_angle = 0;     // leg push direction above the head direction, rad
  double approach_distance = 0;  // how far ahead along the landing curve the bird steers, cm
  double brake_distance = 0;     // distance to the branch where the bird brakes, cm
  double brake_pitch = 0;        // body pitch the bird brakes at, rad
  double perch_radius = 0;       // distance to the branch point at which the bird grips it, cm
};

Species eagle();     // Table 1, Fig. 16 column, plus calibrated parameters
Species starling();  // Table 1, Figs. 17-21 column, plus calibrated parameters
std::vector<Species> species_presets();
// Throws std::invalid_argument naming the first bad parameter, e.g. "f_min > f_max".
void validate(const Species& s);

// Derived quantities.
struct Inertia {
  double x, y, z;  // eq. 12, g cm^2
};
Inertia box_inertia(const Species& s);

}  // namespace aeroflock
