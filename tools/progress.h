// A status line on stderr, rewritten in place, when stderr is a terminal; nothing otherwise, so
// that logs and pipes get only the results.
#pragma once

#include <chrono>
#include <cstddef>
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

// A duration for people: "42 s", "7 min 12 s", "2 h 05 min".
std::string human_duration(double seconds);

// The run's line: simulated time of all (and the share done), the birds, how fast against the
// wall clock (times real time, bird-steps per second) and the wall time left at that pace.
std::string run_progress(double sim_seconds, double total_seconds, size_t birds, double steps, double wall_seconds);

}  // namespace aeroflock
