// The seam between the command line and the ways of stepping a flock (engine/model/simulation.h):
// the Vulkan compute backend (the default) and the CPU reference.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "model/scenario.h"
#include "model/simulation.h"
#include "run/fly_envelope.h"

namespace aeroflock {

struct BackendOptions {
  std::string name = "vulkan";  // "vulkan" or "cpu"
  uint32_t birds = 0;           // > 0: override the scenario's flock sizes
  int device = -1;              // Vulkan device index (-1: prefer a real GPU)
  bool graphics = false;        // the Vulkan device will also render
};

// The Vulkan devices, one line each, for `aeroflock devices`.
std::vector<std::string> vulkan_devices();

// The flock on the backend `options.name` (Vulkan on a device of its own). Throws
// std::runtime_error for a backend that does not exist, gpu::Error when the device cannot start
// or hold the flock.
std::unique_ptr<Simulation> make_simulation(const BackendOptions& options, Scenario scenario);

// Makes simulations of given birds on backend `name` ("cpu" or "vulkan"), all on one Vulkan device
// (started now). Throws like make_simulation.
SimulationFactory simulation_factory(const std::string& name, int device);

// What runs a simulation, in words, for summaries: its device, and the CPU for the reference.
std::string describe_device(const Simulation& simulation);

}  // namespace aeroflock
