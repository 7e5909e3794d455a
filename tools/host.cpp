#include "host.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace aeroflock {

namespace fs = std::filesystem;

bool has_program(const char* name) {
  const std::string command = std::string("command -v ") + name + " >/dev/null 2>&1";
  return std::system(command.c_str()) == 0;
}

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    if (colon != std::string::npos && colon + 2 <= line.size()) return line.substr(colon + 2);
  }
  return "unknown CPU";
}

void check_output_path(const fs::path& path, const std::string& option) {
  auto fail = [&](const std::string& why) {
    throw std::runtime_error(option + " " + path.string() + ": " + why);
  };
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail("is a directory");
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  fs::create_directories(dir, ec);
  if (ec) fail("cannot create directory " + dir.string() + ": " + ec.message());
  fs::path probe = path;
  probe += ".tmp";
  if (!std::ofstream(probe)) fail(std::string("cannot write there: ") + std::strerror(errno));
  fs::remove(probe, ec);
}

}  // namespace aeroflock
