// The simulation the behaviour tests fly, so that they run on the CPU reference and on the Vulkan
// compute shaders alike (flight_cpu.cpp, flight_vulkan.cpp).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include "model/simulation.h"

namespace aeroflock {

// The step a flight takes: its scenario's own; the fast fidelity's in the *_fast test builds
// (AEROFLOCK_FLIGHT_FAST); AEROFLOCK_TEST_DT seconds where that is set (tools/convergence-study.sh
// flies the behaviours at every step of the study). The frame stays as long as the scenario's.
inline Scenario flight_step(Scenario s) {
#ifdef AEROFLOCK_FLIGHT_FAST
  set_dt(s, kFastDt);
#endif
  if (const char* dt = std::getenv("AEROFLOCK_TEST_DT")) set_dt(s, std::stod(dt));
  return s;
}

// False where the backend cannot run here (no Vulkan device): the tests skip. A Vulkan device
// that exists but does not start fails instead (flight_vulkan.cpp).
bool backend_available();
const char* backend_name();
std::unique_ptr<Simulation> make_flight(Scenario scenario, uint32_t birds_override = 0);
// The same with the birds given (their routes and species index the scenario's).
std::unique_ptr<Simulation> make_flight_with(Scenario scenario, std::vector<BirdState> birds);

}  // namespace aeroflock
