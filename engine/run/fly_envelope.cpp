#include "run/fly_envelope.h"

#include <cmath>
#include <map>

#include "run/run_loop.h"

namespace aeroflock {
namespace {

// The envelope's judge as a run's observer: each case's bird judged every frame until it has its
// outcome; the run stops when every one has.
class EnvelopeJudge final : public RunObserver {
 public:
  EnvelopeJudge(std::vector<EnvelopeResult*> results, const Species& species,
                const std::function<void(double)>& progress)
      : results_(std::move(results)),
        judged_(results_.size(), false),
        watches_(results_.size(), TouchdownWatch(kFrameSeconds)),
        left_(results_.size()),
        species_(species),
        progress_(progress) {}

  void frame(Simulation& sim, uint64_t) override {
    const double t = sim.time();
    const std::vector<BirdState>& now = sim.birds();
    std::vector<uint32_t> done;
    for (size_t k = 0; k < results_.size(); ++k) {
      if (retired_[k]) continue;
      watches_[k].sample(t, now[k]);
      if (!judged_[k] &&
          judge_envelope(*results_[k], now[k], species_, t, sim.world().ground_height))
        judged_[k] = true;
      // Judged, and its touch-down followed as long as it settles (a landing's outcome is its
      // grip): no need to fly it on.
      if (judged_[k] && watches_[k].settled(t)) {
        keep_touchdown(k);
        done.push_back(uint32_t(k));
        --left_;
      }
    }
    sim.retire(done);
    if (progress_) progress_(t);
  }
  std::string stop_reason() const override { return left_ == 0 ? "every case judged" : ""; }
  void finish(Simulation& sim) override {
    for (size_t k = 0; k < results_.size(); ++k) {
      if (!judged_[k]) results_[k]->time = sim.time();  // late
      if (!retired_[k]) keep_touchdown(k);
    }
  }

 private:
  // Done with case k: its touch-down (if any) kept, its bird retired.
  void keep_touchdown(size_t k) {
    retired_[k] = true;
    const TouchdownWatch& w = watches_[k];
    if (!w.touchdowns().empty()) results_[k]->touchdown = w.touchdowns().front();
    results_[k]->go_rounds = w.go_rounds();
  }

  std::vector<EnvelopeResult*> results_;
  std::vector<bool> judged_;
  std::vector<TouchdownWatch> watches_;
  std::vector<bool> retired_ = std::vector<bool>(results_.size(), false);
  size_t left_;
  const Species& species_;
  const std::function<void(double)>& progress_;
};

}  // namespace

std::vector<EnvelopeResult> fly_envelope(const Species& species,
                                         const std::vector<EnvelopeCase>& cases,
                                         const SimulationFactory& make,
                                         const std::function<void(double)>& progress, double dt) {
  std::vector<EnvelopeResult> results(cases.size());
  std::map<double, std::vector<size_t>> by_wind;  // one simulation per crosswind
  for (size_t i = 0; i < cases.size(); ++i) by_wind[cases[i].crosswind].push_back(i);

  for (const auto& [wind, indices] : by_wind) {
    std::vector<EnvelopeCase> these;
    std::vector<EnvelopeResult*> judged;
    for (size_t i : indices) {
      these.push_back(cases[i]);
      results[i].c = cases[i];
      results[i].lowest = INFINITY;
      judged.push_back(&results[i]);
    }
    EnvelopeFlight flight = envelope_flight(species, these, dt);
    std::unique_ptr<Simulation> sim = make(flight.scenario, std::move(flight.birds));
    EnvelopeJudge judge(std::move(judged), species, progress);
    run_frames(*sim, {&judge}, {.frames = flight.frames});
  }
  return results;
}

}  // namespace aeroflock
