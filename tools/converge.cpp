#include "converge.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "backend.h"
#include "io/atomic_file.h"
#include "io/paths.h"
#include "io/scenario_file.h"
#include "io/summary.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/flock_geometry.h"
#include "model/statistics.h"
#include "progress.h"
#include "run/fly_envelope.h"
#include "run/run_loop.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;
using glm::dvec3;
using Clock = std::chrono::steady_clock;

constexpr double kLeastPath =
    100.0;  // cm: birds that flew less (perched all along) have no relative error

// One scenario flown at one dt.
struct Run {
  double dt = 0.0;
  std::vector<dvec3> end;    // each bird's position at the comparison time, cm
  std::vector<double> path;  // each bird's distance flown to then, cm
  std::vector<uint32_t> flock;
  std::vector<double> cut;  // s: when each bird's position was taken (its route's end, or the end)
  double wall = 0.0;        // s
  double sim = 0.0;         // s
  uint64_t birds = 0;
  uint64_t nan_birds = 0, below_ground = 0, over_bank = 0, over_pitch = 0;  // birds that ever did
  uint64_t targets_reached = 0, perched = 0;  // perched: at rest on their sites, branch or ground
  std::vector<FlockingSummary> flocking;
  // Against the reference: relative to each bird's distance flown.
  double error_median = 0.0, error_max = 0.0;
  double centroid_error = 0.0;  // the worst flock's centroid, relative to its mean distance flown
  std::string failed;           // what did not hold, in words; empty when everything did
  double criterion() const;     // the error the tolerance applies to
  bool flocks = false;
};

// Flocking birds see their neighbours: any rounding changes who is nearest, so single birds' paths
// part whatever the step (the flock is chaotic); the flock's centroid is what converges.
double Run::criterion() const { return flocks ? centroid_error : error_max; }

// Whether the bird has flown its whole route: through the last target of a route that neither
// loops nor ends on a branch. After it the bird turns back through its target, left or right on
// rounding alone (a symmetric flight meets it exactly behind), so positions are compared here.
bool route_done(const BirdState& b, const World& w) {
  const Route& r = w.routes[b.route];
  return !r.loop && r.branch < 0 && b.targets_reached >= r.targets.size();
}

// Records a run of the study as the run loop flies it: each bird's path until its position is
// taken (at its cut, or where its route ends), velocity-corrected to that time, and what it must
// never do, judged to the end (flight_faults); the wall time of the frames (stepped and waited
// for).
class Recorder final : public RunObserver {
 public:
  Recorder(Run& run, const std::vector<double>& cut, double compare_at, Progress& progress,
           std::string label)
      : run_(run),
        cut_(cut),
        compare_at_(compare_at),
        progress_(progress),
        label_(std::move(label)) {}

  void start(Simulation& sim) override {
    const size_t n = sim.bird_count();
    last_.resize(n);
    nan_.assign(n, 0), below_.assign(n, 0), bank_.assign(n, 0), pitch_.assign(n, 0),
        taken_.assign(n, 0);
    run_.birds = n;
    run_.path.assign(n, 0.0);
    run_.end.resize(n);
    run_.flock.resize(n);
    run_.cut.assign(n, compare_at_);
    const std::vector<BirdState>& start = sim.birds();
    for (size_t i = 0; i < n; ++i) {
      last_[i] = start[i].position;
      run_.flock[i] = start[i].flock;
    }
    since_ = Clock::now();
  }

  void frame(Simulation& sim, uint64_t) override {
    const Scenario& s = sim.scenario();
    const std::vector<BirdState>& now = sim.birds();  // waits for the frame
    run_.wall += std::chrono::duration<double>(Clock::now() - since_).count();
    const double t = sim.time();
    const double half_frame = 0.5 * s.frame_seconds();
    for (size_t i = 0; i < now.size(); ++i) {
      const BirdState& b = now[i];
      const FlightFaults faults = flight_faults(b, s.species[b.species], t, s.world.ground_height);
      if (faults.not_finite) {
        nan_[i] = 1;
        continue;
      }
      below_[i] |= faults.below_ground;
      bank_[i] |= faults.over_bank;
      pitch_[i] |= faults.over_pitch;
      if (taken_[i])
        continue;  // the behaviours are judged to the end, the position where it was taken
      run_.path[i] += glm::length(b.position - last_[i]);
      last_[i] = b.position;
      if (cut_.empty() ? route_done(b, s.world) : t >= cut_[i] - half_frame)
        take(i, b, t, cut_.empty() ? t : cut_[i]);
    }
    if (progress_.due()) {
      char text[160];
      std::snprintf(text, sizeof text, "%s, dt %g ms: t = %.1f of %.1f s", label_.c_str(),
                    s.dt * 1e3, t, compare_at_);
      progress_.show(text);
    }
    since_ = Clock::now();
  }

  void finish(Simulation& sim) override {
    run_.sim = sim.time();
    const std::vector<BirdState>& end = sim.birds();
    for (size_t i = 0; i < end.size(); ++i)
      if (!taken_[i]) take(i, end[i], run_.sim, compare_at_);
    for (size_t i = 0; i < end.size(); ++i) {
      run_.nan_birds += nan_[i];
      run_.below_ground += below_[i];
      run_.over_bank += bank_[i];
      run_.over_pitch += pitch_[i];
    }
    const FlockStatistics stats = flock_statistics(end, sim.scenario().species);
    run_.targets_reached = stats.targets_reached;
    run_.perched = stats.perched + stats.landed;
    run_.flocking = flocking_summary(sim.scenario(), end);
  }

 private:
  // Takes bird i's position at `at` from its state at time t.
  void take(size_t i, const BirdState& b, double t, double at) {
    run_.end[i] = b.position + b.velocity * (at - t);
    run_.cut[i] = at;
    taken_[i] = 1;
  }

  Run& run_;
  const std::vector<double>& cut_;
  double compare_at_;
  Progress& progress_;
  std::string label_;
  std::vector<dvec3> last_;  // each bird's position at the frame before
  std::vector<uint8_t> nan_, below_, bank_, pitch_, taken_;
  Clock::time_point since_;
};

// Flies `scenario` at `dt` to `seconds` (whole 30 ms frames), each bird's position taken at
// `cut[i]` s (empty: where its route ends, or the end) and velocity-corrected to that time.
Run fly(Scenario scenario, double dt, double seconds, const std::vector<double>& cut,
        const ConvergeOptions& options, Progress& progress, const std::string& label) {
  set_dt(scenario, dt);
  Run run;
  run.dt = dt;
  run.flocks = any_flocking(scenario);
  const double compare_at = std::round(seconds / kFrameSeconds) * kFrameSeconds;
  std::unique_ptr<Simulation> sim =
      make_simulation({options.backend, 0, options.device, false}, scenario);
  // The frames that bring it within half a frame of compare_at.
  const Scenario& s = sim->scenario();
  Recorder recorder(run, cut, compare_at, progress, label);
  run_frames(*sim, {&recorder},
             {.frames = s.frames_reaching(compare_at - 0.5 * s.frame_seconds())});
  return run;
}

// Errors against the reference and what no longer holds.
void compare(Run& r, const Run& ref) {
  std::vector<double> errors;
  std::map<uint32_t, std::pair<dvec3, dvec3>> centroids;  // flock: sum of positions, ref's
  std::map<uint32_t, std::pair<double, double>> paths;    // flock: sum of paths, birds
  for (size_t i = 0; i < r.end.size(); ++i) {
    const double d = glm::length(r.end[i] - ref.end[i]);
    if (ref.path[i] >= kLeastPath) errors.push_back(d / ref.path[i]);
    centroids[r.flock[i]].first += r.end[i];
    centroids[r.flock[i]].second += ref.end[i];
    paths[r.flock[i]].first += ref.path[i];
    paths[r.flock[i]].second += 1.0;
  }
  r.error_median = median(errors);
  r.error_max = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
  for (const auto& [f, c] : centroids) {
    const double mean_path = paths[f].first / paths[f].second;
    if (mean_path >= kLeastPath)
      r.centroid_error =
          std::max(r.centroid_error, glm::length(c.first - c.second) / paths[f].second / mean_path);
  }
  std::vector<std::string> failed;
  auto count = [&](uint64_t k, const char* what) {
    if (k) failed.push_back(std::to_string(k) + " " + what);
  };
  count(r.nan_birds, "NaN");
  count(r.below_ground, "below the ground");
  count(r.over_bank, "over-banked");
  count(r.over_pitch, "over-pitched");
  // Every target the reference's birds reached, and as many perched, give or take a bird in a
  // hundred.
  const auto slack = [](uint64_t ref_count) { return ref_count / 100; };
  if (r.targets_reached + slack(ref.targets_reached) < ref.targets_reached)
    failed.push_back(std::to_string(r.targets_reached) + " of the reference's " +
                     std::to_string(ref.targets_reached) + " targets");
  const uint64_t perched_gap =
      r.perched > ref.perched ? r.perched - ref.perched : ref.perched - r.perched;
  if (perched_gap > slack(ref.perched))
    failed.push_back(std::to_string(r.perched) + " perched, the reference " +
                     std::to_string(ref.perched));
  r.failed.clear();
  for (size_t i = 0; i < failed.size(); ++i) r.failed += (i ? ", " : "") + failed[i];
}

struct ScenarioStudy {
  std::string name;
  uint64_t birds = 0;
  bool flocks = false;
  std::vector<Run> runs;  // by dt, the reference first
};

struct EnvelopeStudy {
  std::string species;
  struct Row {
    double dt = 0.0;
    size_t cases = 0, reached = 0;
    std::map<std::string, int> failures;
    double wall = 0.0;
  };
  std::vector<Row> rows;
};

const Names<ConvergeOptions::Envelope> kEnvelopes{{"none", ConvergeOptions::Envelope::none},
                                                  {"quick", ConvergeOptions::Envelope::quick},
                                                  {"sample", ConvergeOptions::Envelope::sample},
                                                  {"whole", ConvergeOptions::Envelope::whole}};

std::vector<EnvelopeCase> envelope_for(ConvergeOptions::Envelope which) {
  if (which == ConvergeOptions::Envelope::quick) return envelope_cases(true);
  if (which == ConvergeOptions::Envelope::whole) return envelope_cases(false);
  return envelope_sample(5, INFINITY);
}

std::string percent(double x) {
  char text[32];
  std::snprintf(text, sizeof text, x < 1e-4 ? "%.2g %%" : "%.3f %%", 100.0 * x);
  return text;
}

nlohmann::ordered_json to_json(const std::vector<ScenarioStudy>& studies,
                               const std::vector<EnvelopeStudy>& env, const ConvergeOptions& o,
                               double largest) {
  using J = nlohmann::ordered_json;
  J j;
  j["seconds"] = o.seconds;
  j["backend"] = o.backend;
  j["reference_dt"] = o.dts.front();
  j["tolerance"] = o.tolerance;
  j["largest_dt"] = largest > 0 ? J(largest) : J(nullptr);
  J scenarios = J::array();
  for (const ScenarioStudy& st : studies) {
    J runs = J::array();
    for (const Run& r : st.runs) {
      J flocks = J::array();
      for (const FlockingSummary& f : r.flocking)
        flocks.push_back({{"name", f.name},
                          {"median_nearest", f.metrics.median_nearest},
                          {"too_close", f.metrics.too_close},
                          {"polarisation", f.metrics.polarisation},
                          {"largest_cluster", f.metrics.largest_cluster}});
      runs.push_back(
          {{"dt", r.dt},
           {"error_median", r.error_median},
           {"error_max", r.error_max},
           {"centroid_error", r.centroid_error},
           {"criterion", r.criterion()},
           {"holds", r.failed.empty()},
           {"failed", r.failed},
           {"nan_birds", r.nan_birds},
           {"below_ground", r.below_ground},
           {"over_bank", r.over_bank},
           {"over_pitch", r.over_pitch},
           {"targets_reached", r.targets_reached},
           {"perched", r.perched},
           {"wall_seconds", r.wall},
           {"bird_seconds_per_second", r.wall > 0 ? double(r.birds) * r.sim / r.wall : 0.0},
           {"flocking", flocks}});
    }
    scenarios.push_back(
        {{"name", st.name}, {"birds", st.birds}, {"flocking", st.flocks}, {"runs", runs}});
  }
  j["scenarios"] = scenarios;
  J envelope = J::array();
  for (const EnvelopeStudy& e : env) {
    J rows = J::array();
    for (const EnvelopeStudy::Row& r : e.rows)
      rows.push_back({{"dt", r.dt},
                      {"cases", r.cases},
                      {"reached", r.reached},
                      {"failures", r.failures},
                      {"wall_seconds", r.wall}});
    envelope.push_back({{"species", e.species}, {"rows", rows}});
  }
  j["envelope"] = envelope;
  return j;
}

}  // namespace

int run_converge(const ConvergeOptions& o) {
  if (!o.json.empty()) check_output_path(o.json, "--json", {".json"});
  if (o.dts.size() < 2)
    throw std::runtime_error("--dts: expected at least two steps (the smallest is the reference)");
  std::vector<double> dts = o.dts;
  std::sort(dts.begin(), dts.end());
  ConvergeOptions options = o;
  options.dts = dts;
  std::vector<std::string> names = o.scenarios;
  if (names.empty())
    for (const BuiltinScenario& b : builtin_scenarios()) names.push_back(b.name);
  std::vector<Scenario> scenarios;
  for (const std::string& name : names)
    scenarios.push_back(load_scenario(name));  // bad names fail first

  const std::string envelope = o.envelope == ConvergeOptions::Envelope::none
                                   ? ""
                                   : " and the envelope (" + name_of(o.envelope, kEnvelopes) + ")";
  std::printf(
      "aeroflock converge: %zu scenario%s%s at %zu steps from %g to %g ms, %g s each, on the %s "
      "backend; "
      "the %g ms step is the reference\n",
      scenarios.size(), scenarios.size() == 1 ? "" : "s", envelope.c_str(), dts.size(),
      dts.front() * 1e3, dts.back() * 1e3, o.seconds, o.backend.c_str(), dts.front() * 1e3);
  std::fflush(stdout);
  Progress progress;
  std::vector<ScenarioStudy> studies;
  for (const Scenario& scenario : scenarios) {
    ScenarioStudy st;
    st.name = scenario.name;
    st.flocks = any_flocking(scenario);
    st.runs.push_back(fly(scenario, dts.front(), o.seconds, {}, options, progress, scenario.name));
    for (size_t k = 1; k < dts.size(); ++k)
      st.runs.push_back(
          fly(scenario, dts[k], o.seconds, st.runs.front().cut, options, progress, scenario.name));
    st.birds = st.runs.front().birds;
    for (Run& r : st.runs) compare(r, st.runs.front());
    progress.clear();
    std::printf("\n%s: %llu bird%s%s\n", st.name.c_str(), (unsigned long long)st.birds,
                st.birds == 1 ? "" : "s",
                st.flocks ? ", flocking (the error is the flock centroid's)" : "");
    std::printf("  %8s  %12s  %12s  %12s  %16s  %s\n", "dt (ms)", "error median", "error max",
                "centroid", "bird-s / s", "holds");
    for (const Run& r : st.runs)
      std::printf("  %8g  %12s  %12s  %12s  %16.4g  %s\n", r.dt * 1e3,
                  percent(r.error_median).c_str(), percent(r.error_max).c_str(),
                  percent(r.centroid_error).c_str(), double(r.birds) * r.sim / r.wall,
                  r.failed.empty() ? "yes" : ("no: " + r.failed).c_str());
    std::fflush(stdout);
    studies.push_back(std::move(st));
  }

  std::vector<EnvelopeStudy> envelopes;
  if (o.envelope != ConvergeOptions::Envelope::none) {
    const std::vector<EnvelopeCase> cases = envelope_for(o.envelope);
    const SimulationFactory make = simulation_factory(o.backend, o.device);
    for (const Species& species : species_presets()) {
      EnvelopeStudy es;
      es.species = species.name;
      for (double dt : dts) {
        const auto t0 = Clock::now();
        const std::vector<EnvelopeResult> results = fly_envelope(
            species, cases, make,
            [&](double t) {
              if (!progress.due()) return;
              char text[160];
              std::snprintf(text, sizeof text, "envelope %s, dt %g ms: t = %.0f s",
                            species.name.c_str(), dt * 1e3, t);
              progress.show(text);
            },
            dt);
        EnvelopeStudy::Row row;
        row.dt = dt;
        row.wall = std::chrono::duration<double>(Clock::now() - t0).count();
        row.cases = results.size();
        for (const EnvelopeResult& r : results) {
          if (r.outcome == Outcome::reached)
            ++row.reached;
          else
            ++row.failures[name(r.outcome)];
        }
        es.rows.push_back(row);
      }
      progress.clear();
      std::printf("\nenvelope, %s (%zu cases):\n  %8s  %10s  %8s  %s\n", es.species.c_str(),
                  cases.size(), "dt (ms)", "reached", "wall (s)", "failures");
      for (const EnvelopeStudy::Row& r : es.rows) {
        std::printf("  %8g  %10zu  %8.1f ", r.dt * 1e3, r.reached, r.wall);
        for (const auto& [what, k] : r.failures) std::printf(" %s %d", what.c_str(), k);
        std::printf("\n");
      }
      std::fflush(stdout);
      envelopes.push_back(std::move(es));
    }
  }

  // The largest step at which everything holds within the tolerance, and every smaller one too.
  double largest = 0.0;
  for (size_t k = 1; k < dts.size(); ++k) {
    bool ok = true;
    for (const ScenarioStudy& st : studies)
      ok = ok && st.runs[k].failed.empty() && st.runs[k].criterion() <= o.tolerance;
    for (const EnvelopeStudy& es : envelopes) ok = ok && es.rows[k].reached == es.rows[0].reached;
    if (!ok) break;
    largest = dts[k];
  }
  if (largest > 0)
    std::printf("\nlargest step at which everything holds and the error stays under %g %%: %g ms\n",
                100 * o.tolerance, largest * 1e3);
  else
    std::printf("\nno step but the reference holds everywhere within %g %%\n", 100 * o.tolerance);

  if (!o.json.empty()) {
    write_text_atomically(o.json, to_json(studies, envelopes, options, largest).dump(2) + "\n");
    std::printf("json             %s\n", o.json.c_str());
  }
  return largest > 0 ? 0 : 1;
}

Command add_converge_command(CLI::App& app, ConvergeOptions& o) {
  CLI::App* cmd = app.add_subcommand("converge",
                                     "The time step's convergence study: every scenario and the "
                                     "envelope at steps of 0.1 to 10 ms");
  cmd->add_option("scenario", o.scenarios,
                  "Built-in scenario names or FILE.toml files (default: every built-in)");
  auto dts_ms = std::make_shared<std::vector<double>>();
  add_list(cmd, "--dts", *dts_ms,
           "Steps in ms, the smallest the reference; a list (default 0.1,0.3,0.5,1,2,3,5,10)")
      ->check(kStepMs);
  cmd->add_option("--seconds", o.seconds, "Seconds flown by each run (default 10)")
      ->check(kSeconds);
  add_backend_option(cmd, o.backend);
  add_device_option(cmd, o.device);
  add_choice(cmd, "--envelope", o.envelope, kEnvelopes,
             "Envelope cases flown at each step: none, quick, sample (every 5th flight) or whole "
             "(default sample)");
  cmd->add_option("--json", o.json, "Write every figure to FILE.json")->check(kPath);
  return {cmd, [&o, dts_ms] {
            if (!dts_ms->empty()) {
              o.dts.clear();
              for (double ms : *dts_ms) o.dts.push_back(ms * 1e-3);
            }
            return run_converge(o);
          }};
}

}  // namespace aeroflock
