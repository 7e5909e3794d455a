// One bird's state: what the simulation carries from step to step. The fields are listed once, in
// bird_state.def; the modes in flight_mode.def.
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace aeroflock {

enum class FlightMode : uint32_t {
#define AF_FLIGHT_MODE(name, value) name = value,
#define AF_LANDING_STAGE(name, value)
#include "flight_mode.def"
#undef AF_FLIGHT_MODE
#undef AF_LANDING_STAGE
};

enum class LandingStage : uint32_t {
#define AF_FLIGHT_MODE(name, value)
#define AF_LANDING_STAGE(name, value) name = value,
#include "flight_mode.def"
#undef AF_FLIGHT_MODE
#undef AF_LANDING_STAGE
};

struct BirdState {
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) cpp_type name = initial;
#include "bird_state.def"
#undef AF_BIRD_FIELD
};

// Seconds in the current mode, from its whole steps of dt.
inline double mode_time(const BirdState& b, double dt) { return double(b.mode_steps) * dt; }
// One more step in the current mode; the count stops at its largest (2^32 - 1 steps: 99 days at
// 2 ms), long past every time a mode is compared with.
inline void count_mode_step(BirdState& b) {
  if (b.mode_steps < UINT32_MAX) ++b.mode_steps;
}
// One more step circling a goal (the same stop).
inline void count_circling_step(BirdState& b) {
  if (b.circling_steps < UINT32_MAX) ++b.circling_steps;
}
// The whole steps of dt a rest of `seconds` lasts: those that start before it ends, less half a
// step (the rest ends on the step nearest its end), within [0, 2^32 - 1].
uint32_t whole_steps(double seconds, double dt);

// Whether every number of a state is finite: a step whose result is not is undone and the bird
// quarantined (step.cpp; bird_step.glsl's all_finite is the same for the compute shaders).
inline bool finite_number(double v) { return std::isfinite(v); }
inline bool finite_number(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool finite_number(const glm::dquat& q) {
  return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}
template <class T>
requires std::is_integral_v<T> || std::is_enum_v<T>
constexpr bool finite_number(T) { return true; }
inline bool all_finite(const BirdState& b) {
  return true
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) &&finite_number(b.name)
#include "bird_state.def"
#undef AF_BIRD_FIELD
      ;
}

}  // namespace aeroflock
