#include "flight.h"

#include "model/simulation.h"

namespace aeroflock {
namespace {

class CpuFlight final : public Flight {
 public:
  CpuFlight(Scenario s, uint32_t birds) : sim_(std::move(s), birds) {}
  void step_frame() override { sim_.step_frame(); }
  void step_once() override { sim_.step_once(); }
  const std::vector<BirdState>& birds() override { return sim_.birds(); }
  double time() const override { return sim_.time(); }
  const World& world() const override { return sim_.world(); }
  const Scenario& scenario() const override { return sim_.scenario(); }

 private:
  Simulation sim_;
};

}  // namespace

bool backend_available() { return true; }
const char* backend_name() { return "cpu"; }
std::unique_ptr<Flight> make_flight(Scenario scenario, uint32_t birds) {
  return std::make_unique<CpuFlight>(std::move(scenario), birds);
}

}  // namespace aeroflock
