#include "io/atomic_file.h"

#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>

namespace aeroflock {

namespace fs = std::filesystem;

fs::path temporary_path(const fs::path& path) {
  fs::path tmp = path;
  tmp += ".tmp";
  return tmp;
}

void write_file_atomically(const fs::path& path,
                           const std::function<void(const fs::path& tmp)>& write) {
  const fs::path tmp = temporary_path(path);
  auto fail = [&](const std::string& why) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("cannot write " + path.string() + (why.empty() ? "" : ": " + why));
  };
  try {
    write(tmp);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fail(ec.message());
}

void write_text_atomically(const fs::path& path, std::string_view text) {
  write_file_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(std::strerror(errno));
    errno = 0;
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    if (!out) throw std::runtime_error(errno ? std::strerror(errno) : "write error");
  });
}

}  // namespace aeroflock
