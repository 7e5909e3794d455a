#include <gtest/gtest.h>

#include "flight.h"
#include "gpu/gpu_simulation.h"
#include "gpu_test_device.h"

namespace aeroflock {
namespace {

// Fails the run if the validation layer reported anything.
class ValidationClean : public ::testing::Environment {
 public:
  void TearDown() override {
    if (const auto& d = testing::test_device(); d.device) {
      EXPECT_EQ(d.device->validation_errors(), 0u) << "Vulkan validation errors";
    }
  }
};
const auto* const kValidation = ::testing::AddGlobalTestEnvironment(new ValidationClean);

}  // namespace

bool backend_available() {
  const auto& d = testing::test_device();
  if (!d.device && !d.error.empty())
    ADD_FAILURE() << "the Vulkan device did not start: " << d.error;
  return d.device != nullptr;
}
const char* backend_name() { return "vulkan"; }
std::unique_ptr<Simulation> make_flight_with(Scenario scenario, std::vector<BirdState> birds) {
  return std::make_unique<gpu::GpuSimulation>(*testing::test_device().device,
                                              flight_step(std::move(scenario)), std::move(birds));
}
std::unique_ptr<Simulation> make_flight(Scenario scenario, uint32_t birds) {
  return std::make_unique<gpu::GpuSimulation>(*testing::test_device().device,
                                              flight_step(std::move(scenario)), birds);
}

}  // namespace aeroflock
