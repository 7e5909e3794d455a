#include "backend.h"

#include <stdexcept>

#include "gpu/device.h"
#include "gpu/gpu_simulation.h"
#include "io/host.h"
#include "model/flock.h"
#include "model/step.h"

namespace aeroflock {

std::vector<std::string> vulkan_devices() {
  std::vector<std::string> lines;
  for (const gpu::DeviceInfo& info : gpu::Device::list_devices())
    lines.push_back(gpu::describe(info));
  return lines;
}

namespace {

// Before a CPU flock is placed: its memory against what the host has available, an error naming
// both. A bird holds its state, the forces of its step and, flocking, its perception; the state
// counts twice, for the vector's growth as the flock is placed (and a snapshot's copy).
void check_host_memory(const Scenario& scenario, uint32_t birds_override) {
  const uint64_t birds = spawn_count(scenario, birds_override);
  const uint64_t per_bird =
      2 * sizeof(BirdState) + sizeof(StepForces) +
      (any_flocking(scenario) ? sizeof(Perception) + 2 * sizeof(uint32_t) : 0);
  const uint64_t available = available_memory();
  if (birds > available / per_bird)
    throw std::runtime_error("--backend cpu: " + std::to_string(birds) + " birds need about " +
                             std::to_string(birds * per_bird) + " bytes of memory (" +
                             std::to_string(per_bird) + " a bird); the host has " +
                             std::to_string(available) + " bytes available, room for " +
                             std::to_string(available / per_bird) + " birds");
}

}  // namespace

std::unique_ptr<Simulation> make_simulation(const BackendOptions& options, Scenario scenario) {
  if (options.name == "cpu") {
    check_host_memory(scenario, options.birds);
    return std::make_unique<CpuSimulation>(std::move(scenario), options.birds);
  }
  if (options.name == "vulkan") {
    gpu::DeviceOptions device = gpu::headless(options.device, false);
    device.graphics = options.graphics;
    return std::make_unique<gpu::GpuSimulation>(std::make_unique<gpu::Device>(device),
                                                std::move(scenario), options.birds);
  }
  throw std::runtime_error("unknown backend \"" + options.name + "\" (available: vulkan, cpu)");
}

SimulationFactory simulation_factory(const std::string& name, int device) {
  if (name == "cpu")
    return [](Scenario s, std::vector<BirdState> birds) -> std::unique_ptr<Simulation> {
      return std::make_unique<CpuSimulation>(std::move(s), std::move(birds));
    };
  if (name != "vulkan")
    throw std::runtime_error("unknown backend \"" + name + "\" (available: vulkan, cpu)");
  std::shared_ptr<gpu::Device> shared = std::make_shared<gpu::Device>(gpu::headless(device, false));
  return [shared](Scenario s, std::vector<BirdState> birds) -> std::unique_ptr<Simulation> {
    return std::make_unique<gpu::GpuSimulation>(*shared, std::move(s), std::move(birds));
  };
}

std::string describe_device(const Simulation& simulation) {
  return simulation.backend() == "cpu" ? simulation.device() + " on " + cpu_model()
                                       : simulation.device();
}

}  // namespace aeroflock
