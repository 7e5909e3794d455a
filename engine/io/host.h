// What the command line asks of the machine it runs on: programs and the CPU.
#pragma once

#include <cstdint>
#include <string>

namespace aeroflock {

// Whether `name` is a program on PATH.
bool has_program(const char* name);

// The bytes the host can give new allocations without swapping: MemAvailable from /proc/meminfo,
// or the free pages (sysconf) where there is no such line.
uint64_t available_memory();

// The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none).
std::string cpu_model();

}  // namespace aeroflock
