// Files written whole or not at all: to a temporary beside the destination, then renamed onto it,
// so that a reader never sees half a file and a failed write leaves the old one (or none).
//
// A temporary is named PATH.aeroflock-PID-N.tmp (PID the writing process, N its count of
// temporaries) and created with O_EXCL: a name only this program writes, never one that was there
// before. So a write removes only its own temporary, and a file of the same name someone else left
// (PATH.tmp, say) is never touched. A process killed outright (SIGKILL) leaves its temporaries;
// remove_stale_temporaries clears those whose process is gone.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string_view>

namespace aeroflock {

// Creates a new empty temporary for `path` (O_EXCL, mode 0666 less the umask) and returns its
// name. Throws std::runtime_error "cannot write PATH: why" when it cannot be created.
std::filesystem::path create_temporary(const std::filesystem::path& path);

// Whether `name` (a file name, no directory) is a temporary of this program's: NAME.aeroflock-PID-N.tmp.
// Sets *pid to its PID when it is.
bool is_temporary_name(std::string_view name, long* pid = nullptr);

// Removes the temporaries in `dir` of processes that no longer run (a killed run's): the files
// named as is_temporary_name says, whose names start with `prefix` ("" any), whose PID is no live
// process. Returns how many were removed; leaves every other file alone.
size_t remove_stale_temporaries(const std::filesystem::path& dir, std::string_view prefix = "");

// Calls write(tmp) to write the whole file at a new create_temporary(path), then renames it onto
// `path`. `write` throws (std::runtime_error with the reason) when it fails. On any failure the
// temporary is removed and std::runtime_error "cannot write PATH: why" is thrown.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write);

// write_file_atomically for text held in memory.
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace aeroflock
