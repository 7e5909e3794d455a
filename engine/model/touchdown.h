// How a bird comes down (issue 40): a watch fed one bird's state at regular times (the tests' and
// the envelope's frames) that measures its touch-downs, on a branch or on the ground, by the
// criteria of docs/MODEL.md "Take-off and landing": the move of its centre at the grip beyond its
// own flight, its mean speed over the ground just before, and how fast its speed falls and its
// body turns once it holds on.
#pragma once

#include <cstddef>
#include <deque>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "bird.h"
#include "constants.h"

namespace aeroflock {

// The speed before a touch-down is averaged over a wingbeat period, or kTouchdownWindow
// (constants.h) when that is longer.
// How long after a touch-down its settling is followed.
inline constexpr double kSettleWatch = 1.0;  // s

struct Touchdown {
  bool on_branch = false;   // perched; else it stood on the ground
  double time = 0.0;        // s: the first sample that holds on
  glm::dvec3 at{0.0};       // cm: its centre then
  double reach = 0.0;       // cm: on a branch, its path's nearest pass of the perch point in the
                            // frame it gripped in (its feet's of the branch point)
  double jump = 0.0;        // cm: its centre's move into that sample beyond speed x interval
  double mean_speed = 0.0;  // cm/s: its path over the ground over the window before, by its time
  double window = 0.0;      // s: that window, max(1 / frequency, kTouchdownWindow)
  double speed_fall = 0.0;  // cm/s^2: the fastest fall of |velocity| over a frame, from the one
                            // it touched down in to kSettleWatch after
  double turn_rate = 0.0;   // rad/s: the fastest turn of the body over a frame after it
  double turn_jump = 0.0;   // rad: the body's turn into it beyond what its rates turned it
};

// The spacing the criteria are measured at: a 30 ms frame (kFrameSeconds).
class TouchdownWatch {
 public:
  // Keeps samples at least `every` seconds apart (the envelope judges its birds every 6 ms; the
  // criteria read 30 ms frames): a sample sooner than that after the last kept is let go, unless
  // the bird holds on, lets go, or starts or stops braking in it.
  explicit TouchdownWatch(double every = 0.0) : every_(every) {}
  // Feeds the bird's state at time t (s); samples come in order.
  void sample(double t, const BirdState& b);
  // Whether its last touch-down has been followed for kSettleWatch (true with none).
  bool settled(double t) const {
    return touchdowns_.empty() || t > touchdowns_.back().time + kSettleWatch;
  }
  // Its touch-downs so far, the last one still being followed for kSettleWatch.
  const std::vector<Touchdown>& touchdowns() const { return touchdowns_; }
  // Go-rounds: braking towards its branch (mode landing), it flew on instead (route.h).
  size_t go_rounds() const { return go_rounds_; }

 private:
  struct Sample {
    double t;
    glm::dvec3 position, velocity;
    glm::dquat attitude;
    glm::dvec3 omega;
    double frequency;
    bool holding;  // perched, or standing on the ground
    bool landing;  // braking towards a branch
  };
  void follow(const Sample& now);
  // The mean speed over the ground between times `from` and `to` (the kept samples').
  double mean_speed(double from, double to) const;
  std::deque<Sample> history_;  // the last window and a bit, oldest first
  std::vector<Touchdown> touchdowns_;
  size_t go_rounds_ = 0;
  double every_;
};

}  // namespace aeroflock
