#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace aeroflock {

Progress::Progress() : enabled_(::isatty(STDERR_FILENO) == 1) {}

bool Progress::due() const {
  return enabled_ && std::chrono::steady_clock::now() - last_ >= std::chrono::milliseconds(200);
}

void Progress::show(const std::string& text) {
  if (!enabled_) return;
  last_ = std::chrono::steady_clock::now();
  std::fprintf(stderr, "\r\033[K  %s", text.c_str());
  std::fflush(stderr);
}

void Progress::clear() {
  if (!enabled_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
}

void Progress::finish() {
  if (enabled_) std::fputs("\n", stderr);
}

}  // namespace aeroflock
