// One bird's state: what the simulation carries from step to step.
#pragma once

#include <cstdint>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace aeroflock {

// How far a bird landing with path control (paper 4.4) has got.
enum class LandingStage : uint32_t {
  none = 0,   // not landing yet
  gate = 1,   // flying to the gate on the branch's perpendicular first
  curve = 2,  // following the landing curve (or, lined up, straight in)
};

enum class FlightMode : uint32_t {
  flying = 0,
  standing = 1,    // on the ground, waiting to take off
  taking_off = 2,  // crouch, then leg push (paper 4.3)
  landing = 3,     // braking on the final approach to a branch (paper 4.4)
  perched = 4,     // at rest on a branch
};

struct BirdState {
  glm::dvec3 position{0.0};  // world, cm
  glm::dvec3 velocity{0.0};  // world, cm/s
  glm::dquat attitude{1.0, 0.0, 0.0, 0.0};  // body to world
  glm::dvec3 omega{0.0};     // body angular velocity, body frame, rad/s
  double phase = 0.0;        // wingbeat phase psi, rad in [0, 2 pi)
  double frequency = 0.0;    // f, Hz
  double amplitude = 0.0;    // amp
  double tail_bend = 0.0;    // phi_bend now, rad (up > 0)
  double tail_twist = 0.0;   // phi_rot now, rad (right side down > 0)
  double mode_time = 0.0;    // seconds spent in the current mode
  double takeoff_time = 0.0; // when a standing bird takes off, s
  glm::dvec3 landing_start{0.0};  // Q1 of the landing curve (paper 4.4)
  glm::dvec3 via_point{0.0};      // P, the middle of the landing curve
  double landing_progress = 0.0;  // how far along the landing curve the bird steers, [0, 1]
  FlightMode mode = FlightMode::flying;
  uint32_t species = 0;
  uint32_t route = 0;
  uint32_t target = 0;        // index into the route's targets; == size: the branch (if any)
  uint32_t targets_reached = 0;
  LandingStage landing_stage = LandingStage::none;
};

}  // namespace aeroflock
