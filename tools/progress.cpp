#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "model/route.h"

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

std::string human_duration(double seconds) {
  char text[48];
  const long s = std::lround(std::max(0.0, seconds));
  if (s < 60)
    std::snprintf(text, sizeof text, "%ld s", s);
  else if (s < 3600)
    std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, s / 60 % 60);
  return text;
}

void Pace::add(double wall, double simulated) {
  samples_.emplace_back(wall, simulated);
  // Keep one sample older than the window, so that the window is always spanned.
  while (samples_.size() > 2 && samples_[1].first <= wall - kWindow)
    samples_.erase(samples_.begin());
}

double Pace::rate() const {
  if (samples_.size() < 2) return 0.0;
  const auto& [w0, s0] = samples_.front();
  const auto& [w1, s1] = samples_.back();
  return w1 - w0 >= 0.5 && s1 > s0 ? (s1 - s0) / (w1 - w0) : 0.0;
}

std::string run_progress(double sim_seconds, double total_seconds, size_t birds, double dt,
                         double pace, std::optional<double> to_go) {
  char text[224];
  int n = std::snprintf(text, sizeof text, "t = %.2f / %.2f s (%.0f %%)   %zu birds", sim_seconds,
                        total_seconds, 100.0 * sim_seconds / total_seconds, birds);
  if (to_go)
    n += std::snprintf(text + n, sizeof text - size_t(n),
                       *to_go >= 1e5 ? "   %.1f km to go" : "   %.0f m to go",
                       *to_go >= 1e5 ? *to_go / 1e5 : *to_go / 100.0);
  if (pace > 0.0)
    std::snprintf(text + n, sizeof text - size_t(n),
                  "   %.3gx real time   %.3g bird-steps/s   %s left", pace,
                  double(birds) * pace / dt,
                  (total_seconds - sim_seconds) / pace < 1.0
                      ? "< 1 s"
                      : human_duration((total_seconds - sim_seconds) / pace).c_str());
  return text;
}

std::optional<double> mean_distance_to_go(const std::vector<BirdState>& birds, const World& w) {
  double sum = 0.0;
  size_t counted = 0;
  for (const BirdState& b : birds) {
    if (b.mode == FlightMode::quarantined) continue;
    if (const std::optional<double> d = distance_to_go(b, w)) sum += *d, ++counted;
  }
  if (counted == 0) return std::nullopt;
  return sum / double(counted);
}

void RunProgress::start(Simulation&) {
  start_ = std::chrono::steady_clock::now();
  pace_.add(0.0, 0.0);
}

double RunProgress::wall() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void RunProgress::frame(Simulation& sim, uint64_t) {
  if (!progress_.due()) return;
  // What the device has finished, not merely what was submitted to it.
  const double done = double(sim.ready_frame()) * sim.scenario().frame_seconds();
  pace_.add(wall(), done);
  // Reading the birds costs a pass over all of them: once a second is enough for a distance.
  const auto now = std::chrono::steady_clock::now();
  if (now - to_go_read_ >= std::chrono::seconds(1)) {
    to_go_read_ = now;
    to_go_ = mean_distance_to_go(*sim.ready_snapshot().birds, sim.world());
  }
  progress_.show(run_progress(done, total_seconds_, sim.bird_count(), sim.scenario().dt,
                              pace_.rate(), to_go_));
}

void RunProgress::finish(Simulation& sim) {
  pace_.add(wall(), sim.time());
  progress_.show(run_progress(sim.time(), total_seconds_, sim.bird_count(), sim.scenario().dt,
                              pace_.rate(), mean_distance_to_go(sim.birds(), sim.world())));
  progress_.finish();
}

}  // namespace aeroflock
