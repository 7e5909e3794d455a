// aeroflock bench: how many birds each backend flies per frame, how the cost of a frame grows with
// the flock, and the Vulkan compute backend against the CPU reference on the same flocks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "options.h"

namespace aeroflock {

struct BenchOptions {
  bool quick = false;  // short smoke run: 1000 and 3000 birds, headless only, no bisection
  std::string json;    // Google-Benchmark-like JSON to this file (written atomically)
  std::string plot;    // PNG through gnuplot
  std::vector<std::string> backends{"vulkan", "cpu"};
  std::vector<std::string> variants;  // headless, solo, render, vtk (empty: all; --quick: headless)
  uint32_t max_birds = 1000000;       // largest flock of the sweep
  int repetitions = 0;                // timed frames per measurement (0: 5 quick, 15 full)
  int device = -1;                    // Vulkan device index
  std::string scenario = "default";   // what every measurement flies (a name or FILE.toml)
  StepOption step;                    // the step instead of the scenario's
  double after = 0.0;                 // s of flight before the timed frames
  uint32_t weak_scaling = 0;          // > 0: under mpirun, a weak-scaling point of that many birds
                                      // a rank (bench_ranks.h)
};

// Runs the benchmark, prints the table on stdout (progress on stderr when it is a terminal).
// Throws std::runtime_error for bad options or when a backend cannot start at all.
int run_bench(const BenchOptions& options);

// `aeroflock bench [SCENARIO]` and its options.
Command add_bench_command(CLI::App& app, BenchOptions& options);

}  // namespace aeroflock
