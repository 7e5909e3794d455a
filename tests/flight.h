// The simulation the behaviour tests fly, so that they run on the CPU reference and on the Vulkan
// compute shaders alike (flight_cpu.cpp, flight_vulkan.cpp).
#pragma once

#include <cstdint>
#include <memory>

#include "model/simulation.h"

namespace aeroflock {

// False where the backend cannot run here (no Vulkan device): the tests skip. A Vulkan device
// that exists but does not start fails instead (flight_vulkan.cpp).
bool backend_available();
const char* backend_name();
std::unique_ptr<Simulation> make_flight(Scenario scenario, uint32_t birds_override = 0);
// The same with the birds given (their routes and species index the scenario's).
std::unique_ptr<Simulation> make_flight_with(Scenario scenario, std::vector<BirdState> birds);

}  // namespace aeroflock
