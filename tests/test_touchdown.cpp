// The touch-down watch (model/touchdown.h): what it measures of hand-made flights.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "model/bird.h"
#include "model/constants.h"
#include "model/touchdown.h"

namespace aeroflock {
namespace {

using glm::dvec3;

BirdState flying(const dvec3& position, const dvec3& velocity, double frequency = 5.0) {
  BirdState b;
  b.position = position;
  b.velocity = velocity;
  b.frequency = frequency;
  b.mode = FlightMode::landing;
  return b;
}

// Today's snap (issue 40): at 2.4 m/s, 68 cm short of the branch, it is put on it, stopped and
// levelled within one 30 ms frame.
TEST(TouchdownWatch, MeasuresTheJumpTheSpeedBeforeAndTheSnapAfter) {
  TouchdownWatch watch;
  const dvec3 v{240.0, 0.0, 0.0};
  double t = 0.0;
  for (int k = 0; k < 20; ++k, t += 0.03) watch.sample(t, flying(v * t, v));  // 5 Hz: 0.2 s
  const dvec3 last = v * (t - 0.03);
  BirdState perched = flying(last + dvec3{68.0 + 240.0 * 0.03, 0.0, 0.0}, dvec3{0.0});
  perched.mode = FlightMode::perched;
  perched.via_point = perched.position + dvec3{0.0, 3.0, 4.0};  // where it will sit
  perched.attitude = glm::angleAxis(radians(30.0), dvec3{0.0, 0.0, 1.0});
  watch.sample(t, perched);
  for (int k = 1; k <= 40; ++k) watch.sample(t + 0.03 * k, perched);
  ASSERT_EQ(watch.touchdowns().size(), 1u);
  const Touchdown& d = watch.touchdowns()[0];
  EXPECT_TRUE(d.on_branch);
  EXPECT_DOUBLE_EQ(d.time, t);
  EXPECT_NEAR(d.jump, 68.0, 1e-9);
  EXPECT_NEAR(d.reach, 5.0, 1e-12);   // its centre 5 cm from the perch point as it grips
  EXPECT_NEAR(d.window, 0.2, 1e-12);  // the wingbeat period: longer than kTouchdownWindow
  EXPECT_NEAR(d.mean_speed, 240.0, 1e-9);
  EXPECT_NEAR(d.speed_fall, 240.0 / 0.03, 1e-6);
  EXPECT_NEAR(d.turn_jump, radians(30.0), 1e-9);  // levelled in the grip, turning at no rate
  EXPECT_EQ(d.turn_rate, 0.0);                    // and still after it
  EXPECT_EQ(watch.go_rounds(), 0u);
}

// A bird that comes to a stop by itself over half a second: no jump, the fall as it slowed, the
// speed before averaged over 100 ms where a wingbeat is shorter; a go-round counted.
TEST(TouchdownWatch, ASmoothStopAndAGoRound) {
  TouchdownWatch watch;
  double t = 0.0;
  BirdState b = flying(dvec3{0.0}, dvec3{100.0, 0.0, 0.0}, 20.0);
  watch.sample(t, b);
  b.mode = FlightMode::flying;  // went round
  watch.sample(t += 0.03, b);
  b.mode = FlightMode::landing;
  dvec3 x{0.0};
  for (int k = 0; k < 20; ++k) {
    const double speed = 100.0 - 5.0 * k;  // falls 5 cm/s a frame: 1.67 m/s^2
    x += dvec3{speed * 0.03, 0.0, 0.0};
    b.position = x;
    b.velocity = dvec3{speed, 0.0, 0.0};
    if (k == 19) b.mode = FlightMode::standing;
    watch.sample(t += 0.03, b);
  }
  ASSERT_EQ(watch.touchdowns().size(), 1u);
  const Touchdown& d = watch.touchdowns()[0];
  EXPECT_FALSE(d.on_branch);
  EXPECT_EQ(d.reach, 0.0);  // measured on a branch only
  EXPECT_LE(d.jump, 1e-9);
  EXPECT_NEAR(d.window, kTouchdownWindow, 1e-12);
  // Its path over the 0.1 s up to the last sample in the air, by 0.1 s: the frames flown at 20, 15
  // and 10 cm/s and the last third of the one at 25 cm/s.
  EXPECT_NEAR(d.mean_speed, (25.0 / 3.0 + 20.0 + 15.0 + 10.0) * 0.03 / 0.1, 1e-9);
  EXPECT_NEAR(d.speed_fall, 5.0 / 0.03, 1e-6);
  EXPECT_EQ(watch.go_rounds(), 1u);
}

// The grip's speed (issue 40): the mean over the ground over the last wingbeats, counted step by
// step (bird.h). A bird whose speed swings between 1 and 3 m/s within each wingbeat (2 m/s on
// average) dips to 1 m/s at an instant; its mean stays 2 m/s, whatever the phase it is read at,
// within the part-wingbeat's share. Then, slowing to 1 m/s, it reads no lower than 1.5 m/s for the
// next wingbeat: an instant's speed would read 1 m/s at once.
TEST(BeatMeanSpeed, IsTheMeanOverTheLastWingbeatsNotAnInstant) {
  BirdState b;
  b.frequency = 10.0;
  b.velocity = dvec3{200.0, 0.0, 0.0};
  steady_beat_path(b);
  EXPECT_NEAR(beat_mean_speed(b), 200.0, 1e-9) << "placed in flight: as if it had flown so";
  const double dt = 1e-4;
  double lowest_instant = 1e9, lowest_mean = 1e9, highest_mean = 0.0;
  auto fly = [&](double speed) {
    const double phase_before = b.phase;
    b.velocity = dvec3{speed, 0.0, 0.0};
    b.phase = std::fmod(b.phase + 2.0 * kPi * b.frequency * dt, 2.0 * kPi);
    count_beat_path(b, phase_before, speed, dt);
  };
  for (int k = 0; k < 5000; ++k) {  // 0.5 s, five wingbeats
    const double speed = 200.0 - 100.0 * std::cos(b.phase);
    fly(speed);
    lowest_instant = std::min(lowest_instant, speed);
    lowest_mean = std::min(lowest_mean, beat_mean_speed(b));
    highest_mean = std::max(highest_mean, beat_mean_speed(b));
  }
  EXPECT_NEAR(lowest_instant, 100.0, 0.1);
  // 200 - 100 sin(theta) / (2 pi + theta) at theta into a wingbeat: within 13 cm/s of 2 m/s.
  EXPECT_GT(lowest_mean, 186.0);
  EXPECT_LT(highest_mean, 214.0);
  for (int k = 0; k < 1000; ++k) {  // a wingbeat at 1 m/s
    fly(100.0);
    // (2 m/s x a wingbeat + 1 m/s x t) / (a wingbeat + t), t up to a wingbeat.
    EXPECT_GT(beat_mean_speed(b), 149.9);
  }
}

}  // namespace
}  // namespace aeroflock
