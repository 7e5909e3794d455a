#include "plot.h"

#include <stdlib.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "io/atomic_file.h"

namespace aeroflock {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& prefix) {
  std::string pattern = (fs::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (!::mkdtemp(pattern.data()))
    throw std::runtime_error("cannot create a temporary directory " + pattern);
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
  // gnuplot's warnings (a range of one point, say) are its own business; its messages are shown
  // only when it fails.
  const fs::path log = dir.path / "gnuplot.log";
  const std::string command =
      "gnuplot " + shell_string(script.string()) + " 2>" + shell_string(log.string());
  if (std::system(command.c_str()) != 0) {
    std::ifstream messages(log);
    const std::string text((std::istreambuf_iterator<char>(messages)),
                           std::istreambuf_iterator<char>());
    throw std::runtime_error(option + ": gnuplot failed writing " + png.string() +
                             (text.empty() ? "" : ":\n" + text));
  }
  // gnuplot draws into the scratch directory; the image reaches `png` through an AtomicFile, which
  // reports a failure there as every output does.
  std::ifstream in(image, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof())
    throw std::runtime_error(option + ": cannot read gnuplot's image " + image.string());
  try {
    write_text_atomically(png, bytes);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(option + ": " + e.what());
  }
}

}  // namespace aeroflock
