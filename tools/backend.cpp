#include "backend.h"

#include <stdexcept>

#include "gpu/device.h"
#include "gpu/gpu_simulation.h"
#include "host.h"

namespace aeroflock {

std::vector<std::string> vulkan_devices() {
  std::vector<std::string> lines;
  for (const gpu::DeviceInfo& info : gpu::Device::list_devices())
    lines.push_back(gpu::describe(info));
  return lines;
}

std::unique_ptr<Simulation> make_simulation(const BackendOptions& options, Scenario scenario) {
  if (options.name == "cpu")
    return std::make_unique<CpuSimulation>(std::move(scenario), options.birds);
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
  if (name != "vulkan") throw std::runtime_error("unknown backend \"" + name + "\" (available: vulkan, cpu)");
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
