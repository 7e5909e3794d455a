// A status line on stderr, rewritten in place, when stderr is a terminal; nothing otherwise, so
// that logs and pipes get only the results.
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "model/bird.h"
#include "model/world.h"
#include "run/run_loop.h"

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

// How fast a run goes now: simulated seconds done (frames the device has finished, not merely
// submitted) against the wall clock, over the last few seconds.
class Pace {
 public:
  // At wall time `wall` (s), `simulated` seconds are done.
  void add(double wall, double simulated);
  // Simulated seconds per wall second over the window; 0 until half a second has been watched.
  double rate() const;

 private:
  static constexpr double kWindow = 3.0;            // s of wall time
  std::vector<std::pair<double, double>> samples_;  // (wall, simulated), oldest first
};

// The run's line: simulated time of all (and the share done), the birds, how far they still
// have to go along their routes on average (`to_go`, cm; none where no route ends), and at `pace`
// (0: not known yet) how fast against the wall clock (times real time, bird-steps per second) and
// the wall time left.
std::string run_progress(double sim_seconds, double total_seconds, size_t birds, double dt,
                         double pace, std::optional<double> to_go = std::nullopt);

// The birds' mean distance_to_go (cm) over those whose routes end and that are not quarantined;
// none without such birds.
std::optional<double> mean_distance_to_go(const std::vector<BirdState>& birds, const World& w);

// The run's progress line as an observer (run/run_loop.h): run_progress at most five times a
// second from the frames the device has finished, and the last line at the end.
class RunProgress final : public RunObserver {
 public:
  explicit RunProgress(double total_seconds) : total_seconds_(total_seconds) {}
  bool reads_every_frame() const override { return false; }
  void start(Simulation& sim) override;
  void frame(Simulation& sim, uint64_t frames) override;
  void finish(Simulation& sim) override;

 private:
  double wall() const;
  double total_seconds_;
  std::optional<double> to_go_;  // cm, read from the birds at most once a second
  std::chrono::steady_clock::time_point to_go_read_{};
  Progress progress_;
  Pace pace_;
  std::chrono::steady_clock::time_point start_{};
};

}  // namespace aeroflock
