#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>

namespace aeroflock {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kTag = ".aeroflock-";
constexpr std::string_view kSuffix = ".tmp";

// The temporaries this process has made (for a name unique within the process).
std::atomic<unsigned long long> g_temporaries{0};

[[noreturn]] void cannot_write(const fs::path& path, const std::string& why) {
  throw std::runtime_error("cannot write " + path.string() + (why.empty() ? "" : ": " + why));
}

// Whether process `pid` exists (a process of another user counts: EPERM).
bool alive(long pid) { return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno != ESRCH); }

}  // namespace

fs::path create_temporary(const fs::path& path) {
  const std::string pid = std::to_string(::getpid());
  // Another N on the rare clash (a file of a process gone that had this PID).
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path tmp = path;
    tmp += std::string(kTag) + pid + "-" + std::to_string(++g_temporaries) + std::string(kSuffix);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return tmp;
    }
    if (errno != EEXIST) cannot_write(path, std::strerror(errno));
  }
  cannot_write(path, "no free temporary name");
}

bool is_temporary_name(std::string_view name, long* pid) {
  // NAME.aeroflock-PID-N.tmp with NAME not empty and PID, N decimal.
  if (!name.ends_with(kSuffix)) return false;
  name.remove_suffix(kSuffix.size());
  const size_t tag = name.rfind(kTag);
  if (tag == std::string_view::npos || tag == 0) return false;
  const std::string_view numbers = name.substr(tag + kTag.size());
  const size_t dash = numbers.find('-');
  if (dash == std::string_view::npos) return false;
  long p = 0;
  unsigned long long n = 0;
  const char* first = numbers.data();
  const char* last = numbers.data() + numbers.size();
  const auto a = std::from_chars(first, first + dash, p);
  const auto b = std::from_chars(first + dash + 1, last, n);
  if (dash == 0 || a.ec != std::errc() || a.ptr != first + dash || b.ec != std::errc() ||
      b.ptr != last || first + dash + 1 == last || p <= 0)
    return false;
  if (pid) *pid = p;
  return true;
}

size_t remove_stale_temporaries(const fs::path& dir, std::string_view prefix) {
  size_t removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    long pid = 0;
    if (!name.starts_with(prefix) || !is_temporary_name(name, &pid) || alive(pid)) continue;
    std::error_code ignored;
    if (it->is_regular_file(ignored) && fs::remove(it->path(), ignored)) ++removed;
  }
  return removed;
}

void write_file_atomically(const fs::path& path,
                           const std::function<void(const fs::path& tmp)>& write) {
  const fs::path tmp = create_temporary(path);
  auto fail = [&](const std::string& why) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    cannot_write(path, why);
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
