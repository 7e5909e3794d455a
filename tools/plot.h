// Plots through gnuplot, for `aeroflock bench --plot` and `aeroflock converge --plot`.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace aeroflock {

// Removes a directory on the way out.
struct TempDir {
  std::filesystem::path path;
  TempDir() = default;
  explicit TempDir(const std::string& prefix);  // a new directory under the system's temporary one
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  TempDir(TempDir&& o) noexcept : path(std::move(o.path)) { o.path.clear(); }
  TempDir& operator=(TempDir&& o) noexcept {
    std::swap(path, o.path);
    return *this;
  }
  ~TempDir();
};

// 'text' quoted for a gnuplot script.
std::string gnuplot_string(const std::string& text);

// Runs the gnuplot script that `write` writes (after the terminal and output lines; its data files
// go in `dir`) and puts the image at `png` atomically: never a half-written image. `option` names
// the command line option in errors. Throws std::runtime_error.
void write_plot_png(
    const std::filesystem::path& png, const std::string& option, int width, int height,
    const std::function<void(std::ostream& script, const std::filesystem::path& dir)>& write);

}  // namespace aeroflock
