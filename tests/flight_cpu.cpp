#include "flight.h"

namespace aeroflock {

bool backend_available() { return true; }
const char* backend_name() { return "cpu"; }
std::unique_ptr<Simulation> make_flight(Scenario scenario, uint32_t birds) {
  return std::make_unique<CpuSimulation>(flight_step(std::move(scenario)), birds);
}
std::unique_ptr<Simulation> make_flight_with(Scenario scenario, std::vector<BirdState> birds) {
  return std::make_unique<CpuSimulation>(flight_step(std::move(scenario)), std::move(birds));
}

}  // namespace aeroflock
