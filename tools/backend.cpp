#include "backend.h"

#include <omp.h>

#include <fstream>
#include <stdexcept>

#include "model/simulation.h"

namespace aeroflock {
namespace {

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    if (colon != std::string::npos && colon + 2 <= line.size()) return line.substr(colon + 2);
  }
  return "unknown CPU";
}

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

 private:
  Simulation simulation_;
};

}  // namespace

std::unique_ptr<Backend> make_backend(const BackendOptions& options, Scenario scenario) {
  if (options.name == "cpu")
    return std::make_unique<CpuBackend>(std::move(scenario), options.birds);
  if (options.name == "vulkan") throw std::runtime_error("vulkan backend not built yet");
  throw std::runtime_error("unknown backend \"" + options.name + "\" (available: cpu)");
}

}  // namespace aeroflock
