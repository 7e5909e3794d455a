// Files written whole or not at all: to a temporary beside the destination, then renamed onto it,
// so that a reader never sees half a file and a failed write leaves the old one (or none).
//
// Every output of the program (VTK frames and trajectories, the .pvd, PNGs, the video, plots, the
// summary and the bench JSON) goes through AtomicFile, so one code path writes the bytes and one
// reports a failure: the reason is always the errno of the system call that failed (pwrite,
// fsync, close or rename), taken at that call, never read later from a library's state.
//
// A temporary is named PATH.aeroflock-PID-N.tmp (PID the writing process, N its count of
// temporaries) and created with O_EXCL: a name only this program writes, never one that was there
// before. So a write removes only its own temporary, and a file of the same name someone else left
// (PATH.tmp, say) is never touched. A process killed outright (SIGKILL) leaves its temporaries;
// remove_stale_temporaries clears those whose process is gone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>

namespace aeroflock {

class AtomicFile {
 public:
  // Creates the temporary of `path` (O_EXCL, mode 0666 less the umask). Throws std::runtime_error
  // "cannot write PATH: why" when it cannot.
  explicit AtomicFile(std::filesystem::path path);
  // Without commit(): closes and removes the temporary; `path` is left as it was.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Appends the bytes at stream()'s position. Buffered: throws std::runtime_error "cannot write
  // PATH: why" when a failure has been met so far (here or earlier), else close() will.
  void write(const void* data, size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }

  // A buffered, seekable stream onto the file (1 MiB held at most), for writers that take an
  // std::ostream (VTK's XML writers). It never throws: a failure sets its badbit and is kept, and
  // close() and commit() throw it.
  std::ostream& stream();

  // Flushes, fsync()s and close()s the temporary: its bytes are on the disk, under the temporary's
  // name still (a probe of whether a directory takes files stops here). Throws std::runtime_error
  // "cannot write PATH: why" (the first failure of any call so far, the temporary removed) instead.
  void close();
  // close(), then renames the temporary onto `path`; throws as close() does. After commit() the
  // object holds nothing.
  void commit();

  // The reason of the first failure ("" while there is none), as strerror gives it.
  const std::string& error() const { return error_; }
  // "cannot write PATH: why": the text every failure is thrown with.
  std::string error_message() const;
  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  class Buffer;
  friend class Buffer;
  // Records the failure `err` (errno; the first failure only) and returns false.
  bool failed(int err);
  [[noreturn]] void fail(int err);  // failed(err), then throw_error()
  [[noreturn]] void throw_error();  // removes the temporary, throws error_message()
  // pwrite(2) until done; false on failure (kept in error_).
  bool write_at(const char* data, size_t size, int64_t offset);
  void discard();

  std::filesystem::path path_, temporary_;
  int fd_ = -1;
  std::string error_;
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
};

// Whether `name` (a file name, no directory) is a temporary of this program's:
// NAME.aeroflock-PID-N.tmp. Sets *pid to its PID when it is.
bool is_temporary_name(std::string_view name, long* pid = nullptr);

// Removes the temporaries in `dir` of processes that no longer run (a killed run's): the files
// named as is_temporary_name says, whose names start with `prefix` ("" any), whose PID is no live
// process. Returns how many were removed; leaves every other file alone.
size_t remove_stale_temporaries(const std::filesystem::path& dir, std::string_view prefix = "");

// An AtomicFile holding `text`, committed.
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace aeroflock
