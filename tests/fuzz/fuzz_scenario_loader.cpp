// libFuzzer target for the scenario loader: any bytes through parse_scenario(), the entry that
// both `aeroflock run FILE.toml` and the built-in scenarios go through. A ScenarioError (or any
// other std::exception, e.g. std::bad_alloc) is the loader refusing the input, a normal outcome;
// a crash, a sanitizer report, a leak, a timeout or an abort is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string_view>

#include "io/scenario_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const aeroflock::Scenario scenario = aeroflock::parse_scenario(text, "fuzz.toml");
    static_cast<void>(scenario);
  } catch (const std::exception&) {
  }
  return 0;
}
