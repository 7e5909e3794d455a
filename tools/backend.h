// The seam between the command line and the ways of stepping a flock: the Vulkan compute
// backend (the default) and the CPU reference.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gpu/device.h"
#include "gpu/gpu_simulation.h"
#include "model/bird.h"
#include "model/scenario.h"

namespace aeroflock {

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;    // as given to --backend
  virtual std::string device() const = 0;  // what runs it, in words
  virtual void step_frame() = 0;           // scenario.steps_per_frame steps of dt
  virtual double time() const = 0;         // simulated seconds so far
  virtual uint64_t steps() const = 0;      // steps per bird so far
  virtual const std::vector<BirdState>& birds() = 0;
  virtual const Scenario& scenario() const = 0;
  // The state one frame back and its time, for exporters: on Vulkan, reading the latest state
  // waits for the device, reading the one before does not (the latest runs meanwhile). lags()
  // says whether there is such a lag; the CPU reference has none and returns the latest.
  virtual bool lags() const { return false; }
  virtual const std::vector<BirdState>& lagged_birds() { return birds(); }
  virtual double lagged_time() const { return time(); }
  // The compute backend's simulation (its birds already on the device), or nullptr.
  virtual gpu::GpuSimulation* gpu_simulation() { return nullptr; }
  virtual const gpu::Device* gpu_device() const { return nullptr; }
};

struct BackendOptions {
  std::string name = "vulkan";
  uint32_t birds = 0;  // > 0: override the scenario's flock sizes
  int device = -1;     // Vulkan device index (-1: prefer a real GPU)
  bool graphics = false;  // the Vulkan device will also render
};

// The Vulkan devices, one line each, for `aeroflock devices`.
std::vector<std::string> vulkan_devices();

// Throws std::runtime_error for a backend that does not exist (or is not built).
std::unique_ptr<Backend> make_backend(const BackendOptions& options, Scenario scenario);

}  // namespace aeroflock
