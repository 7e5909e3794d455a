// One bird's state: what the simulation carries from step to step. The fields are listed once, in
// bird_state.def; the modes in flight_mode.def.
#pragma once

#include <cstdint>

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

}  // namespace aeroflock
