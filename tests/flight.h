// A flock flown by one backend, so that the behaviour tests run on the CPU reference and on the
// Vulkan compute shaders alike (flight_cpu.cpp, flight_vulkan.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "model/bird.h"
#include "model/scenario.h"

namespace aeroflock {

class Flight {
 public:
  virtual ~Flight() = default;
  virtual void step_frame() = 0;  // scenario.steps_per_frame steps
  virtual void step_once() = 0;   // one step (targets move at frame starts only)
  virtual const std::vector<BirdState>& birds() = 0;
  virtual double time() const = 0;
  virtual const World& world() const = 0;  // targets where the birds see them now
  virtual const Scenario& scenario() const = 0;
};

// False where the backend cannot run here (no Vulkan device): the tests skip.
bool backend_available();
const char* backend_name();
std::unique_ptr<Flight> make_flight(Scenario scenario, uint32_t birds_override = 0);

}  // namespace aeroflock
