// Outputs checked before a run: a path that cannot be written fails at once, not after the time
// spent simulating.
#pragma once

#include <filesystem>
#include <string>

namespace aeroflock {

// Makes sure a file can be written at `path`: not a directory, its directory created, and a
// scratch file written and removed at PATH.tmp (where write_file_atomically writes). Throws
// std::runtime_error "WHAT PATH: why" otherwise; `what` names the option or the output.
void check_output_path(const std::filesystem::path& path, const std::string& what);

// Makes sure files can be written in `dir`: creates it (and its parents) and writes and removes a
// scratch file there. Throws std::runtime_error "WHAT DIR: why" otherwise.
void check_writable_dir(const std::filesystem::path& dir, const std::string& what);

}  // namespace aeroflock
