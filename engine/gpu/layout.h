// The flock on the GPU: std430 layouts shared with shaders/compute/layout.glsl, and the packing
// of the CPU reference's state into them. Floats on the device, doubles in the reference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec4.hpp>

#include "model/bird.h"
#include "model/species.h"
#include "model/world.h"

namespace aeroflock::gpu {

// One bird: 128 bytes, eight vec4s.
struct GpuBird {
  glm::vec4 position_phase;      // xyz position (cm), w wingbeat phase
  glm::vec4 velocity_frequency;  // xyz velocity (cm/s), w frequency
  glm::vec4 attitude;            // quaternion x, y, z, w (body to world)
  glm::vec4 omega_amplitude;     // xyz body rates, w amplitude
  glm::vec4 tail_times;          // tail bend, tail twist, mode_time, takeoff_time
  glm::vec4 via_progress;        // xyz P of the landing curve, w landing progress
  glm::vec4 landing_start;       // xyz Q1 of the landing curve, w unused
  glm::uvec4 ids;                // x mode | landing stage << 8 | species << 16, y route,
                                 // z target, w targets reached
};
static_assert(sizeof(GpuBird) == 128);
static_assert(offsetof(GpuBird, velocity_frequency) == 16);
static_assert(offsetof(GpuBird, attitude) == 32);
static_assert(offsetof(GpuBird, omega_amplitude) == 48);
static_assert(offsetof(GpuBird, tail_times) == 64);
static_assert(offsetof(GpuBird, via_progress) == 80);
static_assert(offsetof(GpuBird, landing_start) == 96);
static_assert(offsetof(GpuBird, ids) == 112);

// A species, with the values the step derives from it precomputed: 64 floats.
struct GpuSpecies {
  float mass, inv_inertia_x, inv_inertia_y, inv_inertia_z;
  float f_min, f_max, K_f, amp_min;
  float amp_max, K_a, bend_max, rot_max;
  float tail_min, Ct, ground_k, wing_length;
  float A_arm, A_hand, lag_hand, B_arm;
  float B_hand, C_leadlag, flap_bias, twist_bias;
  float shoulder_x, shoulder_z, arm_length, hand_length;
  float arm_area, hand_area, Cl_max, Cd_0;
  float Cd_90, tail_incidence, tail_hinge_x, tail_arm;  // tail_arm: 2/3 lr
  float tail_area_per_radian, tail_rate, tail_roll_max, turn_rate;
  float dead_band, heading_lead, height_lead, height_band;
  float bank_max, tan_bank_max, steer_full_error, roll_rate;
  float bank_time, stand_height, crouch_time, crouch_depth;
  float leg_force, leg_time, push_angle, approach_distance;
  float brake_distance, brake_pitch, perch_radius, open_tail;  // open_tail: fully open (braking)
  float box_b, pad1, pad2, pad3;  // box_b: for drawing the body
};
static_assert(sizeof(GpuSpecies) == 64 * sizeof(float));

struct GpuTarget {
  glm::vec4 centre_radius;  // where it is now, radius
  glm::vec4 velocity;       // xyz
};
struct GpuRoute {
  uint32_t first;   // into the route-target list
  uint32_t count;
  uint32_t flags;   // 1: loop, 2: path control
  uint32_t branch;  // branch index + 1, 0: none
};
struct GpuBranch {
  glm::vec4 point;
  glm::vec4 direction;
};

// Push constants of the step shader.
struct StepConstants {
  glm::vec4 wind_ground;  // xyz wind (cm/s), w ground height (cm)
  float dt;
  float time;             // at the start of the frame
  uint32_t steps;         // steps this dispatch
  uint32_t bird_count;
  uint32_t turning;       // TurningModel
  uint32_t ground_effect;
  uint32_t pad0, pad1;
};
static_assert(sizeof(StepConstants) == 48);

GpuBird pack(const BirdState& b);
BirdState unpack(const GpuBird& g);
GpuSpecies pack(const Species& s);

// The world's static tables; targets are packed at `time` (they move between frames).
struct GpuWorld {
  std::vector<GpuTarget> targets;
  std::vector<GpuRoute> routes;
  std::vector<uint32_t> route_targets;
  std::vector<GpuBranch> branches;
};
GpuWorld pack(const World& w);
std::vector<GpuTarget> pack_targets(const World& w, double time);

}  // namespace aeroflock::gpu
