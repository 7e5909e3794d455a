// The touch-down watch (model/touchdown.h): what it measures of hand-made flights.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/quaternion.hpp>

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

}  // namespace
}  // namespace aeroflock
