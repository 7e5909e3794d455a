#include "io/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "io/atomic_file.h"

namespace aeroflock {

void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
               const std::vector<uint8_t>& rgba) {
  if (rgba.size() != size_t(width) * height * 4)
    throw std::invalid_argument("write_png: pixel count does not match the size");
  write_file_atomically(path, [&](const std::filesystem::path& tmp) {
    if (!stbi_write_png(tmp.c_str(), int(width), int(height), 4, rgba.data(), int(width * 4)))
      throw std::runtime_error(std::strerror(errno));
  });
}

Rgba read_png(const std::filesystem::path& path) {
  int w = 0, h = 0, channels = 0;
  uint8_t* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (!data) throw std::runtime_error(path.string() + ": " + stbi_failure_reason());
  Rgba image{uint32_t(w), uint32_t(h), std::vector<uint8_t>(data, data + size_t(w) * size_t(h) * 4)};
  stbi_image_free(data);
  return image;
}

}  // namespace aeroflock
