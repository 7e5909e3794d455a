#include "bench_ranks.h"

#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "dist/collectives.h"
#include "dist/distributed.h"
#include "dist/distributed_gpu.h"
#include "io/atomic_file.h"
#include "io/scenario_file.h"

namespace aeroflock {

namespace {

// Frames flown before the clock starts: the cuts settle and the caches warm.
constexpr uint32_t kWarmUpFrames = 3;

template <class T>
T reduced(T mine, MPI_Datatype type, MPI_Op op) {
  T all{};
  MPI_Allreduce(&mine, &all, 1, type, op, MPI_COMM_WORLD);
  return all;
}

}  // namespace

int run_weak_scaling(const BenchOptions& o, const dist::MpiSession& mpi) {
  const int ranks = mpi.ranks();
  const uint32_t per_rank = o.weak_scaling;
  Scenario scenario = load_scenario(o.scenario);
  o.step.apply(scenario);
  if (scenario.flocks.size() != 1)
    throw std::runtime_error("--weak-scaling needs a scenario of one flock (migration-flock)");
  // N0 birds at the scenario's density, then P times as many in a box P times as long along x.
  resize_flock(scenario, 0, per_rank);
  Flock& f = scenario.flocks[0];
  f.count = static_cast<uint32_t>(uint64_t{per_rank} * uint64_t(ranks));
  f.spawn_extent.x *= ranks;
  const uint32_t frames = o.repetitions > 0 ? uint32_t(o.repetitions) : 10;

  // On the first of --backends (Vulkan unless said): a device a rank.
  const std::string backend = o.backends.front();
  std::unique_ptr<dist::DistributedSimulation> flock;
  if (backend == "cpu")
    flock = std::make_unique<dist::DistributedCpuSimulation>(scenario, MPI_COMM_WORLD);
  else
    flock = std::make_unique<dist::DistributedGpuSimulation>(
        dist::rank_device(MPI_COMM_WORLD, o.device), scenario, MPI_COMM_WORLD);
  dist::DistributedSimulation& sim = *flock;
  for (uint32_t k = 0; k < kWarmUpFrames; ++k) sim.step_frame();
  const dist::Traffic before = sim.traffic();
  double ghosts = 0.0, slowest_total = 0.0;
  for (uint32_t k = 0; k < frames; ++k) {
    MPI_Barrier(MPI_COMM_WORLD);
    const double start = MPI_Wtime();
    sim.step_frame();
    ghosts += double(sim.ghost_count());
    slowest_total += reduced(MPI_Wtime() - start, MPI_DOUBLE, MPI_MAX);
  }
  const dist::Traffic& after = sim.traffic();
  const double frame_seconds = slowest_total / frames;
  const double comm = (after.seconds - before.seconds) / frames;
  const double bytes = double(after.bytes_sent - before.bytes_sent) / frames;
  const uint64_t birds = sim.bird_count();
  const uint64_t most = reduced<uint64_t>(birds, MPI_UINT64_T, MPI_MAX);
  const double mean = double(f.count) / ranks;

  // Each rank's row, on rank 0.
  struct Row {
    int rank;
    uint64_t birds;
    double ghosts, bytes, comm;
  };
  const std::vector<Row> rows = dist::gather_to(
      0, MPI_COMM_WORLD, std::vector<Row>{{mpi.rank(), birds, ghosts / frames, bytes, comm}});
  if (!mpi.root()) return 0;

  const double steps = double(scenario.steps_per_frame) * double(f.count);
  std::printf(
      "weak scaling: %d rank%s, %u birds a rank (%u in all), %s lengthened %d times along "
      "x, %u frames of %u steps of %g s\n%s\n",
      ranks, ranks == 1 ? "" : "s", per_rank, f.count, scenario.name.c_str(), ranks, frames,
      scenario.steps_per_frame, scenario.dt, sim.device().c_str());
  std::printf("%6s %10s %10s %12s %14s %10s\n", "rank", "birds", "ghosts", "ghosts/bird",
              "bytes/frame", "comm s");
  nlohmann::ordered_json json_rows = nlohmann::ordered_json::array();
  for (const Row& r : rows) {
    std::printf("%6d %10llu %10.0f %12.4f %14.0f %10.4f\n", r.rank, (unsigned long long)r.birds,
                r.ghosts, r.birds ? r.ghosts / double(r.birds) : 0.0, r.bytes, r.comm);
    json_rows.push_back({{"rank", r.rank},
                         {"birds", r.birds},
                         {"ghosts", r.ghosts},
                         {"bytes_per_frame", r.bytes},
                         {"communication_seconds_per_frame", r.comm}});
  }
  double comm_most = 0.0, bytes_most = 0.0, ghosts_share = 0.0;
  for (const Row& r : rows) {
    comm_most = std::max(comm_most, r.comm);
    bytes_most = std::max(bytes_most, r.bytes);
    if (r.birds) ghosts_share = std::max(ghosts_share, r.ghosts / double(r.birds));
  }
  std::printf("frame            %.4f s (the slowest rank's), %.3g bird-steps/s\n", frame_seconds,
              steps / frame_seconds);
  std::printf("imbalance        %.3f (most birds on a rank over the mean)\n", double(most) / mean);
  std::printf("communication    %.1f %% of the frame on the busiest rank\n",
              100.0 * comm_most / frame_seconds);
  if (!o.json.empty()) {
    nlohmann::ordered_json j = {{"ranks", ranks},
                                {"birds_per_rank", per_rank},
                                {"birds", f.count},
                                {"scenario", scenario.name},
                                {"backend", backend},
                                {"device", sim.device()},
                                {"dt", scenario.dt},
                                {"steps_per_frame", scenario.steps_per_frame},
                                {"frames", frames},
                                {"frame_seconds", frame_seconds},
                                {"bird_steps_per_second", steps / frame_seconds},
                                {"imbalance", double(most) / mean},
                                {"most_ghosts_per_bird", ghosts_share},
                                {"most_bytes_per_frame", bytes_most},
                                {"most_communication_seconds_per_frame", comm_most},
                                {"per_rank", json_rows}};
    write_text_atomically(o.json, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace aeroflock
