// The run summary: flock statistics and the JSON file a run writes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "model/bird.h"
#include "model/flock_geometry.h"
#include "model/flock_structure.h"
#include "model/scenario.h"

namespace aeroflock {

struct FlockStatistics {
  uint64_t birds = 0;
  uint64_t nan_birds = 0;        // quarantined (their state became non-finite), or any non-finite
                                 // position, velocity or attitude component
  glm::dvec3 centroid{0.0};      // mean position of the finite birds, cm
  double mean_speed = 0.0;       // mean |velocity| of the finite birds, cm/s
  uint64_t targets_reached = 0;  // summed over all birds
  uint64_t perched = 0;          // mode perched, on a branch
  uint64_t landed = 0;           // mode perched, on the ground at its site (a species that
                                 // does not perch: route.h, lands_on_ground)
  uint64_t flying = 0;           // in the air: modes flying, landing and taking_off
};

// Pure: statistics of a set of bird states (zeros for none); `species` tells a perch from a
// landing on the ground.
FlockStatistics flock_statistics(const std::vector<BirdState>& birds,
                                 const std::vector<Species>& species);

// A flock that flocks, measured as docs/MODEL.md's "What a flock must show" does.
struct FlockingSummary {
  std::string name;
  FlockMetrics metrics;
};
// Every flock of the scenario that flocks, from the birds' states.
std::vector<FlockingSummary> flocking_summary(const Scenario& scenario,
                                              const std::vector<BirdState>& birds);

// A leg its flock cannot hold for the wind (model/scenario.h: wind_beyond_airspeed), by name
// (`from` empty: the leg from the flock's spawn), and the sentence that reports it: 'flock
// "migrants" cannot hold its leg from "km-525" to "km-550": at 600 m the wind blows 12.0 m/s across
// it, and its birds fly at 10.0 m/s; they head into it and drift'.
struct WindWarning {
  std::string flock, from, target;
  double across = 0.0, against = 0.0, height = 0.0, airspeed = 0.0;  // cm/s, cm/s, cm, cm/s
  std::string sentence() const;
};
std::vector<WindWarning> wind_warnings(const Scenario& scenario);

// A bird quarantined (NaN quarantine, step.cpp): its state became non-finite in step `step`, which
// began at `time`; frozen at its last finite state since.
struct QuarantinedBird {
  uint64_t bird = 0;  // its index in the flock, as --vtk-birds and --camera-bird count
  uint64_t step = 0;  // the step that was not finite (BirdState::quarantined_step)
  double time = 0.0;  // s: when it started, step x dt
  BirdState last;     // its last finite state (mode quarantined)
};
// The quarantined birds, the earliest first (then by index), at most `most` of them; the run's step
// is `dt` long.
std::vector<QuarantinedBird> quarantined_birds(const std::vector<BirdState>& birds, double dt,
                                               size_t most);
// How many the summary lists (nan_birds counts them all).
constexpr size_t kQuarantinedListed = 100;

// One rank's share of a run over many (dist/): its birds and ghosts at the end, what it sent.
struct RankSummary {
  int rank = 0;
  uint64_t birds = 0, ghosts = 0;
  uint64_t migrants_sent = 0, ghosts_sent = 0, bytes_sent = 0, rebalances = 0;
  double communication_seconds = 0.0;  // wall time in its exchanges
};

struct RunSummary {
  std::string backend;  // "cpu"
  std::string device;   // e.g. "cpu reference (8 threads, AMD EPYC ...)"
  std::string scenario;
  std::string scenario_hash;  // Scenario::hash
  bool interrupted = false;   // stopped early (Ctrl-C): sim_seconds is where
  uint64_t steps = 0;         // steps per bird
  double dt = 0.0;
  uint32_t steps_per_frame = 0;
  double sim_seconds = 0.0;
  double wall_seconds = 0.0;
  FlockStatistics stats;
  std::vector<FlockingSummary> flocking;
  std::vector<FlockStructureSummary> structure;  // with --structure-from (run/structure.h)
  std::vector<QuarantinedBird> quarantined;      // the first kQuarantinedListed
  std::vector<WindWarning> wind;                 // legs its flocks cannot hold (wind_warnings)
  std::vector<RankSummary> ranks;                // over many ranks, each one's (else empty)
  std::string signal;  // the signal that stopped the run ("SIGINT", "SIGTERM"), or ""
  std::string error;   // the write error that stopped the run ("cannot write PATH: why"), or ""
  // With --vtk: the most frames (and bytes of bird data) that waited for the writer at once, and
  // the queue's bound in frames (0 without --vtk).
  uint64_t vtk_queue_frames = 0, vtk_queue_bytes = 0, vtk_queue_bound = 0;
};

// The summary as JSON: backend, device, scenario, birds, steps, dt, steps_per_frame, sim_seconds,
// wall_seconds, bird_steps_per_second, nan_birds, centroid, mean_speed, targets_reached, perched,
// landed, flying and, for each flock that flocks, `flocking`: name, birds, median_nearest (cm),
// too_close, polarisation, largest_cluster; `structure`: with --structure-from, each flocking
// flock's figures averaged over its snapshots (units in the file's `units`; null where no
// snapshot measured one), else empty; `quarantined`: bird, time, and its last finite position,
// velocity and attitude (w, x, y, z); `signal` and `error` (null when none) and, with --vtk,
// `vtk_queue` {high_water_frames, high_water_bytes, bound_frames} (else null);
// `wind_beyond_airspeed`: flock, target, across_wind, height, airspeed for each leg its flock
// cannot hold (empty when none); `ranks`: over many ranks, each one's rank, birds, ghosts,
// migrants_sent, ghosts_sent, bytes_sent, rebalances, communication_seconds (null on one).
nlohmann::ordered_json summary_json(const RunSummary& summary);

// Writes summary_json atomically (PATH.tmp, then rename). Throws std::runtime_error naming the
// path on failure, leaving neither PATH.tmp nor a partial PATH behind.
void write_summary(const std::filesystem::path& path, const RunSummary& summary);

}  // namespace aeroflock
