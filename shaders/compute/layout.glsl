// The flock's buffers (std430), mirrored by engine/gpu/layout.h.

struct GpuBird {
  vec4 position_phase;      // xyz position (cm), w wingbeat phase
  vec4 velocity_frequency;  // xyz velocity (cm/s), w frequency
  vec4 attitude;            // quaternion x, y, z, w (body to world)
  vec4 omega_amplitude;     // xyz body rates, w amplitude
  vec4 tail_times;          // tail bend, tail twist, mode_time, takeoff_time
  vec4 via_progress;        // xyz P of the landing curve, w landing progress
  vec4 landing_start;       // xyz Q1 of the landing curve
  uvec4 ids;                // x mode | landing stage << 8 | species << 16, y route, z target,
                            // w targets reached
};

struct Species {
  float mass, inv_inertia_x, inv_inertia_y, inv_inertia_z;
  float f_min, f_max, K_f, amp_min;
  float amp_max, K_a, bend_max, rot_max;
  float tail_min, Ct, ground_k, wing_length;
  float A_arm, A_hand, lag_hand, B_arm;
  float B_hand, C_leadlag, flap_bias, twist_bias;
  float shoulder_x, shoulder_z, arm_length, hand_length;
  float arm_area, hand_area, Cl_max, Cd_0;
  float Cd_90, tail_incidence, tail_hinge_x, tail_arm;
  float tail_area_per_radian, tail_rate, tail_roll_max, turn_rate;
  float dead_band, heading_lead, height_lead, height_band;
  float bank_max, tan_bank_max, steer_full_error, roll_rate;
  float bank_time, stand_height, crouch_time, crouch_depth;
  float leg_force, leg_time, push_angle, approach_distance;
  float brake_distance, brake_pitch, perch_radius, open_tail;
  float box_b, pad1, pad2, pad3;  // box_b: for drawing the body
};

struct Target {
  vec4 centre_radius;
  vec4 velocity;
};

struct Route {
  uint first, count, flags, branch;  // flags: 1 loop, 2 path control; branch: index + 1, 0 none
};

struct Branch {
  vec4 point;
  vec4 direction;
};

// The render shaders read the birds: they define BIRDS_ACCESS as readonly.
#ifndef BIRDS_ACCESS
#define BIRDS_ACCESS
#endif
layout(std430, set = 0, binding = 0) BIRDS_ACCESS buffer Birds { GpuBird birds[]; };
layout(std430, set = 0, binding = 1) readonly buffer SpeciesTable { Species species[]; };
layout(std430, set = 0, binding = 2) readonly buffer Targets { Target targets[]; };
layout(std430, set = 0, binding = 3) readonly buffer Routes { Route routes[]; };
layout(std430, set = 0, binding = 4) readonly buffer RouteTargets { uint route_targets[]; };
layout(std430, set = 0, binding = 5) readonly buffer Branches { Branch branches[]; };


const uint kFlying = 0u, kStanding = 1u, kTakingOff = 2u, kLanding = 3u, kPerched = 4u;
const uint kStageNone = 0u, kStageGate = 1u, kStageCurve = 2u;
