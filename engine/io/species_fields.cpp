#include "io/species_fields.h"

#include "model/constants.h"

namespace aeroflock::io {
namespace {

using enum FileUnit;

constexpr SpeciesField kFields[] = {
    {"wing_area", &Species::wing_area, plain},
    {"mass", &Species::mass, plain},
    {"f_min", &Species::f_min, plain},
    {"f_max", &Species::f_max, plain},
    {"K_f", &Species::K_f, plain},
    {"amp_min", &Species::amp_min, plain},
    {"amp_max", &Species::amp_max, plain},
    {"K_a", &Species::K_a, plain},
    {"box_a", &Species::box_a, plain},
    {"box_b", &Species::box_b, plain},
    {"box_c", &Species::box_c, plain},
    {"tail_length", &Species::tail_length, plain},
    {"bend_max", &Species::bend_max, degrees},
    {"rot_max", &Species::rot_max, degrees},
    {"tail_min", &Species::tail_min, degrees},
    {"Ct", &Species::Ct, plain},
    {"ground_k", &Species::ground_k, plain},
    {"wing_length", &Species::wing_length, plain},
    {"A_arm", &Species::A_arm, degrees},
    {"A_hand", &Species::A_hand, degrees},
    {"lag_hand", &Species::lag_hand, degrees},
    {"B_arm", &Species::B_arm, degrees},
    {"B_hand", &Species::B_hand, degrees},
    {"C_leadlag", &Species::C_leadlag, degrees},
    {"flap_bias", &Species::flap_bias, degrees},
    {"twist_bias", &Species::twist_bias, degrees},
    {"shoulder_x", &Species::shoulder_x, plain},
    {"arm_fraction", &Species::arm_fraction, plain},
    {"arm_area_fraction", &Species::arm_area_fraction, plain},
    {"Cl_max", &Species::Cl_max, plain},
    {"Cd_0", &Species::Cd_0, plain},
    {"Cd_90", &Species::Cd_90, plain},
    {"tail_incidence", &Species::tail_incidence, degrees},
    {"tail_roll_max", &Species::tail_roll_max, degrees},
    {"tail_rate", &Species::tail_rate, degrees_per_second},
    {"turn_rate", &Species::turn_rate, degrees_per_second},
    {"dead_band", &Species::dead_band, degrees},
    {"heading_lead", &Species::heading_lead, plain},
    {"height_lead", &Species::height_lead, plain},
    {"height_band", &Species::height_band, plain},
    {"bank_max", &Species::bank_max, degrees},
    {"steer_full_error", &Species::steer_full_error, degrees},
    {"roll_rate", &Species::roll_rate, degrees_per_second},
    {"bank_time", &Species::bank_time, plain},
    {"stand_height", &Species::stand_height, plain},
    {"crouch_time", &Species::crouch_time, plain},
    {"crouch_depth", &Species::crouch_depth, plain},
    {"leg_force", &Species::leg_force, plain},
    {"leg_time", &Species::leg_time, plain},
    {"push_angle", &Species::push_angle, degrees},
    {"approach_distance", &Species::approach_distance, plain},
    {"brake_distance", &Species::brake_distance, plain},
    {"brake_pitch", &Species::brake_pitch, degrees},
    {"perch_radius", &Species::perch_radius, plain},
};

}  // namespace

std::span<const SpeciesField> species_fields() { return kFields; }

double from_file_unit(double value, FileUnit unit) {
  return unit == plain ? value : radians(value);
}

}  // namespace aeroflock::io
