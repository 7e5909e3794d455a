// aeroflock converge: the time step's convergence study. Flies every built-in scenario and the
// flight envelope at a ladder of time steps and reports, for each, how far the birds end from where
// the smallest step puts them (relative to the distance they flew), whether every behaviour still
// holds, and how fast it runs (docs/convergence.md; tools/convergence_table.py tabulates and plots
// its JSON).
#pragma once

#include <string>
#include <vector>

#include "options.h"

namespace aeroflock {

struct ConvergeOptions {
  std::vector<std::string> scenarios;  // built-in names or FILE.toml (empty: every built-in)
  std::vector<double> dts{0.0001, 0.0003, 0.0005, 0.001,
                          0.002,  0.003,  0.005,  0.01};  // s; the smallest is the reference
  double seconds = 10.0;        // flown by each run; positions compared at the end
  std::string backend = "cpu";  // cpu (double, the reference) or vulkan
  int device = -1;
  // The envelope's cases flown at each step: none, the quick subset, every 5th flight, or all.
  enum class Envelope { none, quick, sample, whole } envelope = Envelope::sample;
  std::string json;         // every figure, to this file
  double tolerance = 0.01;  // the position error allowed, of the distance flown
};

// Returns 0 when at least one step but the reference holds everywhere within the tolerance.
// Throws std::runtime_error for bad options.
int run_converge(const ConvergeOptions& options);

// `aeroflock converge [SCENARIO...]` and its options.
Command add_converge_command(CLI::App& app, ConvergeOptions& options);

}  // namespace aeroflock
