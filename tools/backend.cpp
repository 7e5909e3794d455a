#include "backend.h"

#include <omp.h>

#include <fstream>
#include <stdexcept>

#include "gpu/device.h"
#include "host.h"
#include "gpu/gpu_simulation.h"
#include "model/simulation.h"

namespace aeroflock {
namespace {

// The CPU reference: aeroflock::Simulation, parallel over birds with OpenMP.
class CpuBackend final : public Backend {
 public:
  CpuBackend(Scenario scenario, uint32_t birds) : simulation_(std::move(scenario), birds) {}
  std::string name() const override { return "cpu"; }
  std::string device() const override {
    return "cpu reference (" + std::to_string(omp_get_max_threads()) + " threads, " + cpu_model() +
           ")";
  }
  void step_frame() override { simulation_.step_frame(); }
  double time() const override { return simulation_.time(); }
  uint64_t steps() const override { return simulation_.steps(); }
  const std::vector<BirdState>& birds() override { return simulation_.birds(); }
  const Scenario& scenario() const override { return simulation_.scenario(); }

 private:
  Simulation simulation_;
};

// The compute shaders on a Vulkan device: a frame's steps per dispatch, state read back
// double-buffered.
class VulkanBackend final : public Backend {
 public:
  VulkanBackend(const BackendOptions& options, Scenario scenario)
      : device_([&] {
          gpu::DeviceOptions o = gpu::headless(options.device, false);
          o.graphics = options.graphics;
          return o;
        }()),
        simulation_(device_, std::move(scenario), options.birds) {}
  std::string name() const override { return "vulkan"; }
  std::string device() const override { return device_.name() + " (" + device_.driver() + ")"; }
  void step_frame() override { simulation_.step_frame(); }
  double time() const override { return simulation_.time(); }
  uint64_t steps() const override { return simulation_.steps(); }
  const std::vector<BirdState>& birds() override { return simulation_.birds(); }
  const Scenario& scenario() const override { return simulation_.scenario(); }
  bool lags() const override { return true; }
  const std::vector<BirdState>& lagged_birds() override { return simulation_.previous_birds(); }
  double lagged_time() const override { return simulation_.previous_time(); }
  gpu::GpuSimulation* gpu_simulation() override { return &simulation_; }
  const gpu::Device* gpu_device() const override { return &device_; }

 private:
  gpu::Device device_;
  gpu::GpuSimulation simulation_;
};

}  // namespace

std::vector<std::string> vulkan_devices() {
  std::vector<std::string> lines;
  for (const gpu::DeviceInfo& info : gpu::Device::list_devices()) lines.push_back(gpu::describe(info));
  return lines;
}

std::unique_ptr<Backend> make_backend(const BackendOptions& options, Scenario scenario) {
  if (options.name == "cpu")
    return std::make_unique<CpuBackend>(std::move(scenario), options.birds);
  if (options.name == "vulkan") return std::make_unique<VulkanBackend>(options, std::move(scenario));
  throw std::runtime_error("unknown backend \"" + options.name + "\" (available: vulkan, cpu)");
}

}  // namespace aeroflock
