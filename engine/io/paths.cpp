#include "io/paths.h"

#include <cctype>
#include <stdexcept>

#include "io/atomic_file.h"

namespace aeroflock {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& what, const fs::path& path, const std::string& why) {
  throw std::runtime_error(what + " " + path.string() + ": " + why);
}

// Writes and removes a temporary of `file` (a new name of this program's: nothing that stands there
// is touched); why it could not be written, or "" when it could.
std::string probe(const fs::path& file) {
  try {
    AtomicFile scratch(file);
    scratch.write("probe\n");
    scratch.close();  // fsync and close checked too: a disk reports some failures only there
  } catch (const std::exception& e) {
    const std::string text = e.what(), lead = "cannot write " + file.string() + ": ";
    return text.starts_with(lead) ? text.substr(lead.size()) : text;
  }
  return "";
}

// The directory a path lies in ("." for a bare name; "out" for "out/vtk/").
fs::path directory_of(fs::path path) {
  if (!path.has_filename()) path = path.parent_path();
  return path.parent_path().empty() ? fs::path(".") : path.parent_path();
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

void check_output_path(const fs::path& path, const std::string& what,
                       std::initializer_list<const char*> extensions) {
  std::error_code ec;
  if (extensions.size() > 0) {
    const std::string ext = lower(path.extension().string());
    bool known = false;
    std::string list;
    for (const char* e : extensions) {
      known = known || ext == e;
      list += (list.empty() ? "" : extensions.size() > 2 ? ", " : " or ") + std::string(e);
    }
    if (extensions.size() > 2) list.replace(list.rfind(", "), 2, " or ");
    if (!known) fail(what, path, "expected a file name ending in " + list);
  }
  if (fs::is_directory(path, ec)) fail(what, path, "is a directory");
  const fs::path dir = directory_of(path);
  if (!fs::is_directory(dir, ec))
    fail(what, path, "directory " + dir.string() + " does not exist (create it first)");
  if (const std::string why = probe(path); !why.empty())
    fail(what, path, "cannot write there: " + why);
  remove_stale_temporaries(dir, path.filename().string() + ".");  // a killed run's
}

void check_writable_dir(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    const fs::path parent = directory_of(dir);
    if (!fs::is_directory(parent, ec))
      fail(what, dir, "directory " + parent.string() + " does not exist (create it first)");
    fs::create_directory(dir, ec);
    if (ec) fail(what, dir, "cannot create it: " + ec.message());
  }
  if (const std::string why = probe(dir / ".aeroflock-probe"); !why.empty())
    fail(what, dir, "cannot write there: " + why);
  remove_stale_temporaries(dir);  // a killed run's
}

}  // namespace aeroflock
