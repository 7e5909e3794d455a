// Files for the io tests: a fresh directory under the system's temporary one, a file's text.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace aeroflock::testing {

// An empty directory aeroflock_test_NAME in the temporary directory, created when `create`
// (else only its old contents removed: the code under test makes it).
inline std::filesystem::path fresh_dir(const std::string& name, bool create = true) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("aeroflock_test_" + name);
  std::filesystem::remove_all(dir);
  if (create) std::filesystem::create_directories(dir);
  return dir;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace aeroflock::testing
