#include "io/paths.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "io/atomic_file.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& what, const fs::path& path, const std::string& why) {
  throw std::runtime_error(what + " " + path.string() + ": " + why);
}

// Writes and removes `file`; why it could not be written, or "" when it could.
std::string probe(const fs::path& file) {
  errno = 0;
  std::ofstream out(file);
  if (!out) return std::strerror(errno ? errno : EIO);  // and whatever stands there is left alone
  out << "probe\n";
  out.close();
  const int err = errno;
  std::error_code ignored;
  fs::remove(file, ignored);
  return out ? std::string() : std::strerror(err ? err : EIO);
}

}  // namespace

void check_output_path(const fs::path& path, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail(what, path, "is a directory");
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  fs::create_directories(dir, ec);
  if (ec) fail(what, path, "cannot create directory " + dir.string() + ": " + ec.message());
  if (const std::string why = probe(temporary_path(path)); !why.empty())
    fail(what, path, "cannot write there: " + why);
}

void check_writable_dir(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) fail(what, dir, "cannot create it: " + ec.message());
  if (const std::string why = probe(dir / ".aeroflock-probe"); !why.empty())
    fail(what, dir, "cannot write there: " + why);
}

}  // namespace aeroflock
