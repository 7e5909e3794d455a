#include "touchdown.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "body.h"
#include "scenario.h"

namespace aeroflock {

namespace {
bool holds_on(FlightMode m) { return m == FlightMode::perched || m == FlightMode::standing; }

}  // namespace

void TouchdownWatch::follow(const Sample& now) {
  // The rates over at least `every` (a frame of the criteria), from the latest sample that long
  // before: the speed's from the frame of the touch-down on, the body's turn from the touch-down on
  // (in the frame before it the bird still flies, and turns as it flies; its turn into the
  // touch-down is turn_jump's).
  Touchdown& d = touchdowns_.back();
  const Sample* before = &history_.front();
  const Sample* turned_from = nullptr;
  for (const Sample& s : history_)
    if (s.t <= now.t - every_ * (1.0 - 1e-9)) {
      before = &s;
      if (s.t >= d.time) turned_from = &s;
    }
  if (!turned_from && now.t > d.time)
    for (const Sample& s : history_)
      if (s.t == d.time) turned_from = &s;  // within a frame of the touch-down
  const double dt = now.t - before->t;
  if (dt > 0.0)
    d.speed_fall =
        std::max(d.speed_fall, (glm::length(before->velocity) - glm::length(now.velocity)) / dt);
  if (turned_from && now.t > turned_from->t)
    d.turn_rate = std::max(
        d.turn_rate, turn_angle(turned_from->attitude, now.attitude) / (now.t - turned_from->t));
}

double TouchdownWatch::mean_speed(double from, double to) const {
  // The path over the ground between the samples (a chord a frame: a flapping bird's speed swings
  // within a wingbeat, its path does not), the first frame's share of its chord from `from` on.
  double path = 0.0;
  const Sample* last = nullptr;
  for (const Sample& s : history_) {
    if (s.t > to) break;
    if (last && s.t > from && s.t > last->t) {
      const double share = std::min(1.0, (s.t - from) / (s.t - last->t));
      path += share * glm::length(s.position - last->position);
    }
    last = &s;
  }
  const double start = std::max(from, history_.front().t);
  return to > start ? path / (to - start) : 0.0;
}

void TouchdownWatch::sample(double t, const BirdState& b) {
  const Sample now{t,       b.position,  b.velocity,       b.attitude,
                   b.omega, b.frequency, holds_on(b.mode), b.mode == FlightMode::landing};
  // A little under `every`, so that frames of exactly that length are all kept; a sample that
  // holds on or lets go is kept whenever it comes.
  if (!history_.empty() && t - history_.back().t < every_ * (1.0 - 1e-9) &&
      now.holding == history_.back().holding && now.landing == history_.back().landing)
    return;
  if (!history_.empty()) {
    const Sample& before = history_.back();
    if (before.landing && b.mode == FlightMode::flying) ++go_rounds_;
    if (now.holding && !before.holding) {
      // A touch-down: the move into it beyond the flight, and the speed over the window before.
      Touchdown d;
      d.on_branch = b.mode == FlightMode::perched;
      d.time = t;
      d.at = now.position;
      // Its feet met the branch on its path in that frame: the chord's nearest pass of the point.
      if (d.on_branch) {
        const glm::dvec3 chord = now.position - before.position;
        const double length2 = glm::dot(chord, chord);
        const double u =
            length2 > 0.0
                ? std::clamp(glm::dot(b.via_point - before.position, chord) / length2, 0.0, 1.0)
                : 0.0;
        d.reach = glm::length(before.position + u * chord - b.via_point);
      }
      d.jump = glm::length(now.position - before.position) -
               glm::length(before.velocity) * (t - before.t);
      d.turn_jump =
          turn_angle(before.attitude, now.attitude) - glm::length(before.omega) * (t - before.t);
      d.window = std::max(before.frequency > 0.0 ? 1.0 / before.frequency : 0.0, kTouchdownWindow);
      d.mean_speed = mean_speed(before.t - d.window, before.t);
      touchdowns_.push_back(d);
      follow(now);
    } else if (!touchdowns_.empty() && t <= touchdowns_.back().time + kSettleWatch &&
               before.holding) {
      follow(now);
    }
  }
  history_.push_back(now);
  // Keep the window before a touch-down now (a wingbeat or kTouchdownWindow) and a frame more.
  const double keep = std::max(b.frequency > 0.0 ? 1.0 / b.frequency : 0.0, kTouchdownWindow) +
                      std::max(every_, kFrameSeconds);
  while (history_.size() > 2 && history_.front().t < t - keep) history_.pop_front();
}

}  // namespace aeroflock
