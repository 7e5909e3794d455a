#include "plot.h"

#include <stdlib.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include "io/atomic_file.h"

namespace aeroflock {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& prefix) {
  std::string pattern = (fs::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("cannot create a temporary directory " + pattern);
  path = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  if (!path.empty()) fs::remove_all(path, ec);
}

std::string gnuplot_string(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

namespace {

std::string shell_string(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

void write_plot_png(const fs::path& png, const std::string& option, int width, int height,
                    const std::function<void(std::ostream&, const fs::path&)>& write) {
  TempDir dir("aeroflock-plot");
  const fs::path image = dir.path / "plot.png";
  const fs::path script = dir.path / "plot.gp";
  {
    std::ofstream gp(script);
    const bool cairo = std::system("gnuplot -e 'set terminal' 2>&1 | grep -q pngcairo") == 0;
    gp << "set terminal " << (cairo ? "pngcairo" : "png") << " size " << width << "," << height
       << (cairo ? " font 'sans,10'" : "") << "\n";
    gp << "set output " << gnuplot_string(image.string()) << "\n";
    write(gp, dir.path);
  }
  const std::string command = "gnuplot " + shell_string(script.string());
  if (std::system(command.c_str()) != 0) throw std::runtime_error(option + ": gnuplot failed writing " + png.string());
  try {
    write_file_atomically(png, [&](const fs::path& tmp) {
      std::error_code ec;
      fs::copy_file(image, tmp, fs::copy_options::overwrite_existing, ec);
      if (ec) throw std::runtime_error(ec.message());
    });
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(option + ": " + e.what());
  }
}

}  // namespace aeroflock
