// Images out: PNG files, written whole or not at all; and read back (reference images).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace aeroflock {

// Writes `rgba` (width x height, top row first) as a PNG: to a temporary name, then renamed.
// Throws std::runtime_error naming the path on failure.
void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
               const std::vector<uint8_t>& rgba);

struct Rgba {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> pixels;  // top row first
};
// Reads a PNG (or any image stb_image reads) as RGBA. Throws std::runtime_error naming the path.
Rgba read_png(const std::filesystem::path& path);

}  // namespace aeroflock
