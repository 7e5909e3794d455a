// A status line on stderr, rewritten in place, when stderr is a terminal; nothing otherwise, so
// that logs and pipes get only the results.
#pragma once

#include <chrono>
#include <string>

namespace aeroflock {

class Progress {
 public:
  Progress();
  // Whether a line updated every frame is due again: at most five times a second.
  bool due() const;
  // Replaces the line with `text`.
  void show(const std::string& text);
  // Rubs the line out (before a result is printed on stdout).
  void clear();
  // Leaves the last line standing and ends it.
  void finish();

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace aeroflock
