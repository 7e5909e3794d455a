// Outputs checked before a run: a path that cannot be written fails at once, not after the time
// spent simulating.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <string>

namespace aeroflock {

// Nothing is created outside what was asked for: a file's directory must exist, and a directory
// is created only inside one that exists (as mkdir does, not mkdir -p), so that a typo does not
// leave a tree of directories behind.

// Makes sure a file can be written at `path`: not a directory, its directory existing, and a
// scratch file written and removed beside it (an AtomicFile's temporary, never committed; a
// killed run's temporaries of PATH are removed). With
// `extensions` (".png", ...; compared without case) the name must end in one of them. Throws
// std::runtime_error "WHAT PATH: why" otherwise; `what` names the option or the output.
void check_output_path(const std::filesystem::path& path, const std::string& what,
                       std::initializer_list<const char*> extensions = {});

// Makes sure files can be written in `dir`: creates it when its parent exists and writes and
// removes a scratch file there (and a killed run's temporaries: remove_stale_temporaries). Throws
// std::runtime_error "WHAT DIR: why" otherwise.
void check_writable_dir(const std::filesystem::path& dir, const std::string& what);

}  // namespace aeroflock
