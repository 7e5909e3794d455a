// The flight envelope flown (model/envelope.h says the cases and how each is judged): one
// simulation per crosswind through the run loop, its birds judged every frame by an observer
// until every case has its outcome. `aeroflock envelope`, `aeroflock converge` and the tests fly
// it so.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "model/envelope.h"
#include "model/simulation.h"

namespace aeroflock {

// Makes the simulation that flies the cases (the CPU reference or the compute shaders).
using SimulationFactory =
    std::function<std::unique_ptr<Simulation>(Scenario scenario, std::vector<BirdState> birds)>;

// Flies every case and judges it, stepped by `dt`. `progress` (may be empty) is told the
// simulated seconds of each frame.
std::vector<EnvelopeResult> fly_envelope(const Species& species,
                                         const std::vector<EnvelopeCase>& cases,
                                         const SimulationFactory& make,
                                         const std::function<void(double)>& progress = {},
                                         double dt = kPaperDt);

}  // namespace aeroflock
