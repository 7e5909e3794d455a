#include "output/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <stdexcept>

#include "io/atomic_file.h"

namespace aeroflock {

void write_png(const std::filesystem::path& path, uint32_t width, uint32_t height,
               const std::vector<uint8_t>& rgba) {
  if (rgba.size() != size_t(width) * height * 4)
    throw std::invalid_argument("write_png: pixel count does not match the size");
  AtomicFile file(path);
  // stb hands the encoded bytes over in pieces; the first failure is kept and thrown by commit().
  const auto put = [](void* context, void* data, int size) {
    auto* out = static_cast<AtomicFile*>(context);
    if (out->error().empty()) out->stream().write(static_cast<const char*>(data), size);
  };
  if (!stbi_write_png_to_func(put, &file, int(width), int(height), 4, rgba.data(), int(width * 4)))
    throw std::runtime_error("cannot write " + path.string() + ": the PNG encoder failed");
  file.commit();
}

Rgba read_png(const std::filesystem::path& path) {
  int w = 0, h = 0, channels = 0;
  uint8_t* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (!data) throw std::runtime_error(path.string() + ": " + stbi_failure_reason());
  Rgba image{uint32_t(w), uint32_t(h),
             std::vector<uint8_t>(data, data + size_t(w) * size_t(h) * 4)};
  stbi_image_free(data);
  return image;
}

}  // namespace aeroflock
