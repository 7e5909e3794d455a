// Built-in scenarios (scenarios/*.toml compiled in) and loading by name or path.
#include <toml++/toml.h>

#include <filesystem>
#include <string_view>
#include <vector>

#include "io/embedded_scenarios.h"
#include "io/scenario_file.h"
#include "io/words.h"

namespace aeroflock {

std::vector<BuiltinScenario> builtin_scenarios() {
  std::vector<BuiltinScenario> out;
  for (const io::EmbeddedFile& file : io::embedded_scenarios()) {
    std::string description;
    try {
      description = toml::parse(file.text)["simulation"]["description"].value_or(std::string());
    } catch (const toml::parse_error&) {
      // A broken built-in shows up when it is loaded; the listing just lacks its description.
    }
    out.push_back({file.name, description, file.text});
  }
  return out;
}

Scenario load_scenario(std::string_view name_or_path) {
  std::string names;
  std::vector<std::string_view> builtins;
  for (const io::EmbeddedFile& file : io::embedded_scenarios()) {
    if (name_or_path == file.name)
      return parse_scenario(file.text, "scenarios/" + std::string(file.name) + ".toml");
    names += (names.empty() ? "" : ", ") + std::string(file.name);
    builtins.push_back(file.name);
  }
  const std::filesystem::path path(name_or_path);
  std::error_code ec;
  if (path.extension() == ".toml" || std::filesystem::exists(path, ec))
    return read_scenario_file(path);
  throw ScenarioError("unknown scenario \"" + std::string(name_or_path) + "\"" +
                      did_you_mean(name_or_path, builtins) + ": neither a built-in (" + names +
                      ") nor a .toml file");
}

}  // namespace aeroflock
