#include <gtest/gtest.h>

#include "flight.h"
#include "gpu/device.h"
#include "gpu/gpu_simulation.h"

namespace aeroflock {
namespace {

// One device for the whole test program, with the validation layer on.
gpu::Device* device() {
  static std::unique_ptr<gpu::Device> d = []() -> std::unique_ptr<gpu::Device> {
    try {
      if (gpu::Device::list_devices().empty()) return nullptr;
      return std::make_unique<gpu::Device>(gpu::headless(-1, true));
    } catch (const gpu::Error&) {
      return nullptr;
    }
  }();
  return d.get();
}

// Fails the run if the validation layer reported anything.
class ValidationClean : public ::testing::Environment {
 public:
  void TearDown() override {
    if (device()) {
      EXPECT_EQ(device()->validation_errors(), 0u) << "Vulkan validation errors";
    }
  }
};
const auto* const kValidation = ::testing::AddGlobalTestEnvironment(new ValidationClean);

class VulkanFlight final : public Flight {
 public:
  VulkanFlight(Scenario s, uint32_t birds) : sim_(*device(), std::move(s), birds) {}
  void step_frame() override { sim_.step_frame(); }
  void step_once() override { sim_.step(1); }
  const std::vector<BirdState>& birds() override { return sim_.birds(); }
  double time() const override { return sim_.time(); }
  const World& world() const override { return sim_.world(); }
  const Scenario& scenario() const override { return sim_.scenario(); }

 private:
  gpu::GpuSimulation sim_;
};

}  // namespace

bool backend_available() { return device() != nullptr; }
const char* backend_name() { return "vulkan"; }
std::unique_ptr<Flight> make_flight(Scenario scenario, uint32_t birds) {
  return std::make_unique<VulkanFlight>(std::move(scenario), birds);
}

}  // namespace aeroflock
