// The scenarios/*.toml files, compiled in by embed_scenarios.cmake.
#pragma once

#include <span>

namespace aeroflock::io {

struct EmbeddedFile {
  const char* name;  // file stem
  const char* text;
};

// Sorted by name. Defined in the generated embedded_scenarios.cpp.
std::span<const EmbeddedFile> embedded_scenarios();

}  // namespace aeroflock::io
