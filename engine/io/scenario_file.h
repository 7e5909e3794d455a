// Scenario files: TOML in, aeroflock::Scenario out. Lengths in cm, speeds in cm/s, angles in
// degrees and angular rates in deg/s in the file; radians inside.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "model/scenario.h"

namespace aeroflock {

// Every bad input: "FILE:LINE:COLUMN: error: KEY: what was expected" (or "FILE: error: ..."
// where there is no line, e.g. a file that cannot be read).
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The largest scenario text: 16 MiB, some 10^5 targets and more; a file past it (or /dev/zero) is
// an error before it is read.
inline constexpr size_t kMaxScenarioBytes = 16u << 20;

// Reads a scenario file: a regular file of at most kMaxScenarioBytes. The scenario's name
// defaults to the file stem.
Scenario read_scenario_file(const std::filesystem::path& path);
// Parses scenario text (at most kMaxScenarioBytes) in time linear in its size, with no state
// outside the call; `source_name` names it in errors and gives the default name (its stem).
Scenario parse_scenario(std::string_view text, std::string_view source_name);

// The scenarios in scenarios/*.toml, embedded at build time.
struct BuiltinScenario {
  std::string name;         // file stem, e.g. "fig16-circling-eagle"
  std::string description;  // [simulation] description
  std::string text;         // the TOML text
};
std::vector<BuiltinScenario> builtin_scenarios();

// A built-in name, or a path to a .toml file.
Scenario load_scenario(std::string_view name_or_path);

}  // namespace aeroflock
