// What the command line asks of the machine it runs on: programs and the CPU.
#pragma once

#include <string>

namespace aeroflock {

// Whether `name` is a program on PATH.
bool has_program(const char* name);

// The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none).
std::string cpu_model();

}  // namespace aeroflock
