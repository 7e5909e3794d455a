#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <vector>

namespace aeroflock {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kTag = ".aeroflock-";
constexpr std::string_view kSuffix = ".tmp";

// The temporaries this process has made (for a name unique within the process).
std::atomic<unsigned long long> g_temporaries{0};

// Whether process `pid` exists (a process of another user counts: EPERM).
bool alive(long pid) { return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno != ESRCH); }

}  // namespace

// The file's bytes pass through a window of 1 MiB: the bytes at offsets [base_, base_ + filled_),
// written out (pwrite) when the writer moves outside it or it is full, and at close(). A writer
// that seeks back to fill in what it reserved (VTK's offsets) and comes back, within the window,
// costs no system call: a file under 1 MiB is one write, and memory stays bounded whatever the size
// (a frame of a million birds, a long run's trajectories). flush() writes nothing: the bytes go out
// with the window, and a failure is kept for close() (and shown as the stream's badbit once met).
class AtomicFile::Buffer : public std::streambuf {
 public:
  explicit Buffer(AtomicFile& file) : file_(file), bytes_(size_t(1) << 20) { reset(0); }

  // Writes the window out; the next one starts at the current offset.
  bool write_out() {
    mark();
    const int64_t at = here();
    const bool ok = filled_ == 0 || file_.write_at(bytes_.data(), filled_, base_);
    reset(at);
    return ok;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!write_out()) return traits_type::eof();
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    *pptr() = traits_type::to_char_type(c);
    pbump(1);
    return c;
  }
  std::streamsize xsputn(const char* data, std::streamsize n) override {
    if (n <= epptr() - pptr()) {
      std::memcpy(pptr(), data, size_t(n));
      pbump(int(n));
      return n;
    }
    // More than the window holds: out with the window, then these bytes straight after it.
    if (!write_out() || !file_.write_at(data, size_t(n), base_)) return 0;
    reset(base_ + n);
    return n;
  }
  int sync() override { return file_.error_.empty() ? 0 : -1; }
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    mark();
    end_ = std::max(end_, base_ + int64_t(filled_));
    const int64_t to = off + (dir == std::ios_base::beg   ? 0
                              : dir == std::ios_base::cur ? here()
                                                          : end_);
    if (to < 0) return pos_type(off_type(-1));
    if (to >= base_ && to <= base_ + int64_t(filled_)) {  // inside the window
      setp(bytes_.data(), bytes_.data() + bytes_.size());
      pbump(int(to - base_));
      return pos_type(off_type(to));
    }
    if (!write_out()) return pos_type(off_type(-1));
    reset(to);
    return pos_type(off_type(to));
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
    return seekoff(off_type(pos), std::ios_base::beg, which);
  }

 private:
  int64_t here() const { return base_ + (pptr() - pbase()); }
  void mark() { filled_ = std::max(filled_, size_t(pptr() - pbase())); }
  void reset(int64_t base) {
    end_ = std::max(end_, base_ + int64_t(filled_));
    base_ = base;
    filled_ = 0;
    setp(bytes_.data(), bytes_.data() + bytes_.size());
  }

  AtomicFile& file_;
  std::vector<char> bytes_;
  int64_t base_ = 0;   // the window's offset in the file
  size_t filled_ = 0;  // bytes of the window written to (the furthest the writer has been)
  int64_t end_ = 0;    // the file's size, the window's bytes counted
};

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)) {
  const std::string pid = std::to_string(::getpid());
  // Another N on the rare clash (a file of a process gone that had this PID).
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    fs::path tmp = path_;
    tmp += std::string(kTag) + pid + "-" + std::to_string(++g_temporaries) + std::string(kSuffix);
    fd_ = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0)
      temporary_ = tmp;
    else if (errno != EEXIST)
      fail(errno);
  }
  if (fd_ < 0) {
    error_ = "no free temporary name";
    throw_error();
  }
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!temporary_.empty()) ::unlink(temporary_.c_str());
  temporary_.clear();
}

std::string AtomicFile::error_message() const {
  return "cannot write " + path_.string() + (error_.empty() ? "" : ": " + error_);
}

bool AtomicFile::failed(int err) {
  if (error_.empty()) error_ = std::strerror(err);
  return false;
}

void AtomicFile::fail(int err) {
  failed(err);
  throw_error();
}

void AtomicFile::throw_error() {
  const std::string message = error_message();
  discard();
  throw std::runtime_error(message);
}

bool AtomicFile::write_at(const char* data, size_t size, int64_t offset) {
  if (!error_.empty()) return false;
  if (fd_ < 0) return failed(EBADF);  // written after close()
  while (size > 0) {
    const ssize_t n = ::pwrite(fd_, data, size, off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return failed(n < 0 ? errno : EIO);
    data += n;
    size -= size_t(n);
    offset += n;
  }
  return true;
}

void AtomicFile::write(const void* data, size_t size) {
  stream().write(static_cast<const char*>(data), std::streamsize(size));
  if (!error_.empty()) throw_error();
}

std::ostream& AtomicFile::stream() {
  if (!stream_) {
    buffer_ = std::make_unique<Buffer>(*this);
    stream_ = std::make_unique<std::ostream>(buffer_.get());
  }
  return *stream_;
}

void AtomicFile::close() {
  if ((buffer_ && !buffer_->write_out()) || !error_.empty()) throw_error();
  if (fd_ < 0) return;
  // The bytes on the disk before the name: after a crash the file is the old one or the new one
  // whole, never an empty or short new one.
  if (::fsync(fd_) != 0) fail(errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(errno);
}

void AtomicFile::commit() {
  if (temporary_.empty() && error_.empty())
    throw std::logic_error("AtomicFile::commit: nothing to commit");
  close();
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) fail(errno);
  temporary_.clear();
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

void write_text_atomically(const fs::path& path, std::string_view text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

}  // namespace aeroflock
