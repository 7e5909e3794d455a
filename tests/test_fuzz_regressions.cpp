// Every input the scenario loader's fuzzer found (tests/fuzz-regressions/, docs/TESTING.md "Fuzz
// findings"): each gives a clean ScenarioError naming the file, or a scenario that validates; never
// a crash, a sanitizer report (the asan preset runs this too), a hang or another exception.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "io/scenario_file.h"

namespace aeroflock {
namespace {

std::vector<std::filesystem::path> regression_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(AEROFLOCK_FUZZ_REGRESSIONS))
    if (entry.is_regular_file() && entry.path().filename() != ".keep")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(FuzzRegressions, EachGivesACleanErrorOrAValidScenario) {
  const std::vector<std::filesystem::path> files = regression_files();
  ASSERT_FALSE(files.empty()) << "no files in " << AEROFLOCK_FUZZ_REGRESSIONS;
  for (const std::filesystem::path& file : files) {
    SCOPED_TRACE(file.string());
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const std::string name = file.filename().string();
    try {
      const Scenario s = parse_scenario(text.str(), name);
      EXPECT_NO_THROW(validate(s));
    } catch (const ScenarioError& e) {
      // "NAME:LINE:COLUMN: error: ..." or, for the whole scenario, "NAME: error: ...".
      const std::regex clean(
          "^" + std::regex_replace(name, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
          R"((:[0-9]+:[0-9]+)?: error: .+)");
      EXPECT_TRUE(std::regex_search(std::string(e.what()), clean)) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a ScenarioError: " << e.what();
    }
  }
}

}  // namespace
}  // namespace aeroflock
