// Files written whole or not at all: to PATH.tmp beside the destination, then renamed onto it, so
// that a reader never sees half a file and a failed write leaves the old one (or none).
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace aeroflock {

// PATH.tmp: where PATH is written before it is renamed into place.
std::filesystem::path temporary_path(const std::filesystem::path& path);

// Calls write(tmp) to write the whole file at temporary_path(path), then renames it onto `path`.
// `write` throws (std::runtime_error with the reason) when it fails. On any failure the temporary
// is removed and std::runtime_error "cannot write PATH: why" is thrown.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& tmp)>& write);

// write_file_atomically for text held in memory.
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace aeroflock
