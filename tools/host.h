// What the command line asks of the machine it runs on: programs, the CPU, writable paths.
#pragma once

#include <filesystem>
#include <string>

namespace aeroflock {

// Whether `name` is a program on PATH.
bool has_program(const char* name);

// The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none).
std::string cpu_model();

// Makes sure `path` can be written before time is spent on a run: creates its directory and a
// scratch file beside it. Throws "OPTION PATH: why" otherwise.
void check_output_path(const std::filesystem::path& path, const std::string& option);

}  // namespace aeroflock
