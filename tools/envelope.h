// aeroflock envelope: flies a species through the grid of engine/model/envelope.h and prints how
// many cases succeed, by kind and by each dimension of the grid, and the cases that fail.
#pragma once

#include <string>

#include "model/scenario.h"
#include "options.h"

namespace aeroflock {

struct EnvelopeOptions {
  std::string species = "starling";  // a preset, or FILE.toml whose last [[species]] is flown
  std::string backend = "cpu";       // cpu or vulkan
  int device = -1;                   // Vulkan device index
  std::string json;                  // every case with its outcome, to this file
  bool quick = false;                // a small subset of short flights
  double dt = kPaperDt;              // s
};

// Returns 0 when every case succeeds, 1 otherwise; throws for bad options.
int run_envelope(const EnvelopeOptions& options);

// `aeroflock envelope` and its options.
Command add_envelope_command(CLI::App& app, EnvelopeOptions& options);

}  // namespace aeroflock
