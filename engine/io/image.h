// Images out: PNG files, written whole or not at all.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace aeroflock {

// Writes `rgba` (width x height, top row first) as a PNG: to a temporary name, then renamed.
// Throws std::runtime_error naming the path on failure.
void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
               const std::vector<uint8_t>& rgba);

}  // namespace aeroflock
