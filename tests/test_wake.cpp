// The wake (engine/model/wake.h): the lifting line's circulation, the tip vortices' field against
// the closed forms of a vortex pair, the finite core, the wavy wake at the retarded phase, and the
// lateral place where a follower's wing meets the most upwash.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "model/constants.h"
#include "model/flock.h"
#include "model/species.h"
#include "model/step.h"
#include "model/wake.h"
#include "model/wingbeat.h"

namespace aeroflock {
namespace {

using glm::dvec3;

// A starling flying along +x at 10 m/s, level, carrying its weight.
WakeSource level_starling(double amplitude = 0.0, double frequency = 0.0) {
  const Species s = starling();
  WakeSource w;
  w.position = dvec3{1000.0, 2000.0, -500.0};
  w.air_velocity = dvec3{1000.0, 0.0, 0.0};
  w.lift = s.mass * kGravity;
  w.amplitude = amplitude;
  w.frequency = frequency;
  w.phase = 1.0;
  return w;
}

// The swirl of an infinite vortex line at h from its axis (Burnham-Hallock core).
double swirl(double circulation, double h, double core) {
  return circulation / (2.0 * kPi) * h / (h * h + core * core);
}

TEST(Wake, TheCirculationCarriesTheLift) {
  const Species s = starling();
  const double lift = s.mass * kGravity, airspeed = 1000.0;
  const double circulation = wake_circulation(s, lift, airspeed);
  EXPECT_NEAR(kAirDensity * airspeed * circulation * vortex_span(s), lift, 1e-9 * lift);
  EXPECT_NEAR(vortex_span(s), kPi / 4.0 * s.box_c, 1e-12);
  EXPECT_EQ(wake_circulation(s, lift, 0.0), 0.0);
}

// Far behind, the two half-lines are the infinite pair: between them, at their height, each blows
// down with its swirl at half the vortex span; outboard of one the other's opposite swirl leaves
// the upwash.
TEST(Wake, FarBehindItIsAPairOfVortices) {
  const Species s = starling();
  const WakeSource w = level_starling();
  const double behind = 100.0 * s.box_c;
  const dvec3 place = vortex_place(s, w, behind);
  const double circulation = wake_circulation(s, w.lift, 1000.0), core = wake_core(s);
  const dvec3 station = w.position + dvec3{-behind, place.y, 0.0};
  const dvec3 centre = wake_velocity(s, w, station);
  EXPECT_NEAR(centre.y, -2.0 * swirl(circulation, place.z, core), 1e-4 * std::fabs(centre.y));
  EXPECT_NEAR(centre.x, 0.0, 1e-9);
  EXPECT_NEAR(centre.z, 0.0, 1e-9);
  for (double out : {0.5 * place.z, place.z, 2.0 * place.z}) {
    const dvec3 v = wake_velocity(s, w, station + dvec3{0.0, 0.0, place.z + out});
    const double expected =
        swirl(circulation, out, core) - swirl(circulation, 2.0 * place.z + out, core);
    EXPECT_GT(v.y, 0.0) << "upwash outboard";
    EXPECT_NEAR(v.y, expected, 1e-4 * expected);
    // The left side mirrors the right.
    const dvec3 m = wake_velocity(s, w, station - dvec3{0.0, 0.0, place.z + out});
    EXPECT_NEAR(m.y, v.y, 1e-9 * v.y);
    EXPECT_NEAR(m.z, -v.z, 1e-9 + 1e-9 * std::fabs(v.z));
  }
}

// The upwash outboard is largest a core radius from the vortex, and the field is finite on its
// axis and at the bird itself.
TEST(Wake, TheCoreKeepsTheFieldFinite) {
  const Species s = starling();
  const WakeSource w = level_starling();
  const double behind = 20.0 * s.box_c, core = wake_core(s);
  const dvec3 place = vortex_place(s, w, behind);
  const dvec3 axis = w.position + dvec3{-behind, place.y, place.z};
  const dvec3 on_axis = wake_velocity(s, w, axis);
  // On its own axis a vortex induces nothing: what is left there is the other one's downwash.
  const double circulation = wake_circulation(s, w.lift, 1000.0);
  EXPECT_NEAR(on_axis.y, -swirl(circulation, 2.0 * place.z, core),
              1e-3 * swirl(circulation, 2.0 * place.z, core));
  const dvec3 at_bird = wake_velocity(s, w, w.position);
  EXPECT_TRUE(std::isfinite(at_bird.x) && std::isfinite(at_bird.y) && std::isfinite(at_bird.z));
  double best = -1.0, best_out = 0.0;
  for (double out = 0.0; out < 10.0 * core; out += 0.01 * core) {
    const double up = wake_velocity(s, w, axis + dvec3{0.0, 0.0, out}).y;
    if (up > best) best = up, best_out = out;
  }
  EXPECT_NEAR(best_out, core, 0.05 * core);
}

// A flapping bird's wake is wavy: at each station behind it the vortices lie where its wingtips
// were when they shed it, distance / airspeed ago, and one wavelength (airspeed / frequency)
// further back they lie there again.
TEST(Wake, AFlappingWakeLiesWhereTheWingtipsWere) {
  const Species s = starling();
  const WakeSource w = level_starling(1.0, 10.0);
  const double wavelength = 1000.0 / 10.0;
  double lowest = 1e9, highest = -1e9;
  for (double behind = 150.0; behind < 150.0 + wavelength; behind += 5.0) {
    const dvec3 place = vortex_place(s, w, behind);
    const double phase = w.phase - 2.0 * kPi * 10.0 * behind / 1000.0;
    const dvec3 tip = right_wingtip(s, phase, 1.0, 0.0);
    EXPECT_NEAR(place.y, kWakeVortexSpan * tip.y, 1e-9);
    EXPECT_NEAR(place.z, kWakeVortexSpan * tip.z, 1e-9);
    const dvec3 again = vortex_place(s, w, behind + wavelength);
    EXPECT_NEAR(again.y, place.y, 1e-9);
    lowest = std::min(lowest, place.y);
    highest = std::max(highest, place.y);
    // The strongest downwash on the centre line is at the vortices' height there.
    double best = 0.0, best_y = 0.0;
    const dvec3 station = w.position + dvec3{-behind, 0.0, 0.0};
    for (double y = place.y - 20.0; y <= place.y + 20.0; y += 0.25) {
      const double down = -wake_velocity(s, w, station + dvec3{0.0, y, 0.0}).y;
      if (down > best) best = down, best_y = y;
    }
    EXPECT_NEAR(best_y, place.y, 0.5) << behind << " cm behind";
  }
  // The wake waves by the wingtips' beat, pi / 4 of it.
  EXPECT_GT(highest - lowest, 20.0);
}

// A follower of the same span level with the wake, 3 spans behind: the upwash its wing meets,
// weighted by an elliptic loading along its span (what its induced power's saving integrates,
// Lissaman and Shollenberg 1970), is largest with its centre between one vortex span (its inner
// tip vortex on the leader's outer one) and one span (wingtips touching) outboard of the leader's:
// 0.855 spans, the wingtips overlapping by 0.145 of the span (0.86-0.88 for point vortices with
// cores of 0.05 to 0.005 spans, the same integral by hand). Straight behind, it meets downwash.
TEST(Wake, AFollowerMeetsTheMostUpwashOneVortexSpanOut) {
  const Species s = starling();
  const WakeSource w = level_starling();
  const double b = s.box_c, behind = 3.0 * b;
  const double y = vortex_place(s, w, behind).y;
  auto upwash = [&](double lateral) {
    double sum = 0.0, weights = 0.0;
    for (int k = 0; k < 200; ++k) {
      const double z = -0.5 * b + (k + 0.5) * b / 200.0;
      const double weight = std::sqrt(1.0 - std::pow(2.0 * z / b, 2.0));
      sum += weight * wake_velocity(s, w, w.position + dvec3{-behind, y, lateral + z}).y;
      weights += weight;
    }
    return sum / weights;
  };
  double best = -1e9, best_lateral = 0.0;
  for (double lateral = 0.3 * b; lateral < 1.5 * b; lateral += 0.005 * b) {
    const double up = upwash(lateral);
    if (up > best) best = up, best_lateral = lateral;
  }
  RecordProperty("best_lateral_spans", std::to_string(best_lateral / b));
  EXPECT_GT(best_lateral, vortex_span(s));
  EXPECT_LT(best_lateral, b);
  EXPECT_GT(best, 0.0);
  EXPECT_LT(upwash(0.0), 0.0) << "straight behind: downwash";
}

// Over one wingbeat, the mean of a starling's wing force (world: x ahead, y up) flying level at
// cruise speed, as one step at each of 40 phases, with the wake of one ahead of it `behind` spans
// behind and `across` spans to its right (level with its wake), or alone.
dvec3 mean_wing_force(double behind, double across, bool wake) {
  const Species s = starling();
  BirdState b;
  b.position = dvec3{0.0, 3000.0, 0.0};
  b.velocity = dvec3{s.cruise_speed, 0.0, 0.0};
  b.frequency = 0.5 * (s.f_min + s.f_max);
  b.amplitude = 0.8;
  b.flocking = kSeesFlock | kFeelsWakes;
  BirdState leader = b;
  leader.lift = s.mass * kGravity;
  leader.position += dvec3{behind * s.box_c, 0.0, -across * s.box_c};
  Perception seen;
  seen.neighbours = 1;
  seen.direction = dvec3{1.0, 0.0, 0.0};
  seen.airspeed = s.cruise_speed;
  if (wake) {
    seen.wakes = 1;
    seen.wake[0] = {leader.position, leader.velocity,  leader.attitude, leader.lift,
                    leader.phase,    leader.frequency, leader.amplitude};
    // Level with the leader's wake where the follower meets it.
    b.position.y += vortex_place(s, seen.wake[0], behind * s.box_c).y;
  }
  World world;  // a target far ahead
  Target ahead;
  ahead.centre = b.position + dvec3{1e6, 0.0, 0.0};
  world.targets.push_back(ahead);
  world.routes.push_back(Route{"r", {0}});
  world.move_targets(0.0);
  dvec3 sum{0.0};
  for (int k = 0; k < 40; ++k) {
    BirdState one = b;
    one.phase = 2.0 * kPi * k / 40.0;
    StepForces f;
    step_bird(one, s, world, 0, 1e-4, &f, &seen);
    sum += f.wing[0] + f.wing[1] + f.wing[2] + f.wing[3];
  }
  return sum / 40.0;
}

// Its wings meet the wake (issue 43): in the upwash outboard of the bird ahead, 0.855 spans out
// and behind, its wings lift 4.8 % of its weight more over a beat (what lets it beat less to hold
// its height); straight behind, in the downwash, 6.0 % less. The wing force barely turns forward
// (by 7e-5 of the weight): the steeper air adds drag (eq. 2) as it turns the lift. Alone, or with
// the wake 20 spans beside it, nothing changes.
TEST(Wake, AFollowersWingsMeetTheUpwashAndTheDownwash) {
  const Species s = starling();
  const dvec3 alone = mean_wing_force(0.855, 0.855, false);
  const dvec3 upwash = mean_wing_force(0.855, 0.855, true);
  const dvec3 downwash = mean_wing_force(0.855, 0.0, true);
  const dvec3 far = mean_wing_force(0.855, 20.0, true);
  const double weight = s.mass * kGravity;
  RecordProperty("lift_gain_upwash", std::to_string((upwash.y - alone.y) / weight));
  RecordProperty("thrust_gain_upwash", std::to_string((upwash.x - alone.x) / weight));
  RecordProperty("lift_loss_downwash", std::to_string((alone.y - downwash.y) / weight));
  EXPECT_GT(upwash.y - alone.y, 0.01 * weight);
  EXPECT_GT(alone.y - downwash.y, 0.01 * weight);
  EXPECT_NEAR(far.y, alone.y, 1e-3 * weight);
}

}  // namespace
}  // namespace aeroflock
