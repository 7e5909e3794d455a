// docs/MODEL.md's behaviours 1-8, each with its quantitative criterion, on one backend: built with
// flight_cpu.cpp (the CPU reference) and with flight_vulkan.cpp (the compute shaders). The
// paper's figures are the built-in scenarios (scenarios/fig*.toml), so what users run is what is
// tested; cruise, climb and descent are small scenarios written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "flight.h"
#include "io/scenario_file.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/control.h"
#include "model/envelope.h"
#include "model/flock_geometry.h"
#include "model/route.h"
#include "model/simulation.h"
#include "model/species.h"
#include "model/tail.h"
#include "model/touchdown.h"
#include "stub_winged.h"
#include "touchdown_criteria.h"

namespace aeroflock {
namespace {

using glm::dvec3;

// Runs `sim` for `seconds`, calling `each_frame` after every frame.
void run(Simulation& sim, double seconds, const std::function<void(Simulation&)>& each_frame) {
  while (sim.time() < seconds - 1e-9) {
    sim.step_frame();
    each_frame(sim);
  }
}

// Runs `sim` step by step until `seconds`, calling `each_step` after every step.
void run_steps(Simulation& sim, double seconds, const std::function<void(Simulation&)>& each_step) {
  while (sim.time() < seconds - 1e-9) {
    sim.step(1);
    each_step(sim);
  }
}

bool finite(const BirdState& b) {
  auto ok = [](const dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  return ok(b.position) && ok(b.velocity) && ok(b.omega) && std::isfinite(b.attitude.w) &&
         std::isfinite(b.attitude.x) && std::isfinite(b.attitude.y) && std::isfinite(b.attitude.z);
}

// One bird of the preset `species` at (0, 30 m, 0) flying along +x at its cruise_speed (10 m/s
// for the paper's) towards a target `ahead` cm ahead and `above` cm higher.
Scenario straight_flight(const std::string& species, double ahead, double above) {
  double cruise = 0.0;
  for (const Species& s : species_presets())
    if (s.name == species) cruise = s.cruise_speed;
  const std::string toml = R"(
[simulation]
duration = 30.0
[[targets]]
name = "goal"
centre = [)" + std::to_string(ahead) +
                           ", " + std::to_string(3000.0 + above) + R"(, 0.0]
radius = 200.0
[[routes]]
name = "r"
targets = ["goal"]
[[flocks]]
name = "f"
species = ")" + species + R"("
route = "r"
centre = [0.0, 3000.0, 0.0]
speed = )" + std::to_string(cruise) +
                           R"(
random_phase = false
)";
  return parse_scenario(toml, "straight.toml");
}

const Species& species_of(Simulation& sim, const BirdState& b) {
  return sim.scenario().species[b.species];
}

// --- 1. Cruise: height within +-1 m after 2 s, f and amp settled strictly inside their ranges,
// and the tail closed (phi = phi_min) for much of the time: the height control's bends open it
// the rest of the time.
class Cruise : public ::testing::TestWithParam<std::string> {};

TEST_P(Cruise, HoldsHeightWithFrequencyAndAmplitudeInside) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const auto flight = make_flight(straight_flight(GetParam(), 1e6, 0.0));
  Simulation& sim = *flight;
  const Species& sp = sim.scenario().species[sim.birds()[0].species];
  double y_lo = 1e9, y_hi = -1e9, f_lo = 1e9, f_hi = -1e9, a_lo = 1e9, a_hi = -1e9;
  int frames = 0, closed = 0;
  run(sim, 30.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    if (s.time() < 2.0) return;
    y_lo = std::min(y_lo, b.position.y), y_hi = std::max(y_hi, b.position.y);
    f_lo = std::min(f_lo, b.frequency), f_hi = std::max(f_hi, b.frequency);
    a_lo = std::min(a_lo, b.amplitude), a_hi = std::max(a_hi, b.amplitude);
    ++frames;
    if (tail_opening(sp, b.tail_bend, b.tail_twist) == sp.tail_min) ++closed;
  });
  RecordProperty("height_range_cm",
                 std::to_string(y_lo - 3000) + ".." + std::to_string(y_hi - 3000));
  RecordProperty("frequency_range", std::to_string(f_lo) + ".." + std::to_string(f_hi));
  RecordProperty("amplitude_range", std::to_string(a_lo) + ".." + std::to_string(a_hi));
  RecordProperty("tail_closed_fraction", std::to_string(double(closed) / frames));
  EXPECT_GE(y_lo, 3000.0 - 100.0);
  EXPECT_LE(y_hi, 3000.0 + 100.0);
  EXPECT_GT(f_lo, sp.f_min);
  EXPECT_LT(f_hi, sp.f_max);
  EXPECT_GT(a_lo, sp.amp_min);
  EXPECT_LT(a_hi, sp.amp_max);
  EXPECT_GT(double(closed) / frames, 0.3) << "the tail is closed for much of a straight cruise";
}

// --- 2. Climb and descent: a target 10 m above (below) and 100 m ahead is reached; f and amp
// rise (fall) at K_f and K_a (eqs. 4, 5) at first.
struct VerticalCase {
  std::string species;
  double above;
};
void PrintTo(const VerticalCase& c, std::ostream* os) {
  *os << c.species << " to " << c.above << " cm";
}
class ClimbDescent : public ::testing::TestWithParam<VerticalCase> {};

TEST_P(ClimbDescent, ReachesTheTargetWithFrequencyAndAmplitudeFollowingEqs4And5) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const VerticalCase c = GetParam();
  const auto flight = make_flight(straight_flight(c.species, 10000.0, c.above));
  Simulation& sim = *flight;
  const BirdState start = sim.birds()[0];
  const Species& sp = species_of(sim, start);
  const Target& goal = sim.world().targets[0];
  double reached_at = -1.0;
  BirdState at_half_second;
  run(sim, 20.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    if (s.time() <= 0.5) at_half_second = b;
    if (reached_at < 0 && glm::distance(b.position, goal.centre) <= goal.radius)
      reached_at = s.time();
  });
  RecordProperty("reached_at_s", std::to_string(reached_at));
  EXPECT_GT(reached_at, 0.0) << "the sphere " << c.above << " cm above is not entered";
  const double sign = c.above > 0 ? 1.0 : -1.0;
  const double t = mode_time(at_half_second, sim.scenario().dt);  // flying since t = 0
  EXPECT_NEAR(at_half_second.frequency,
              std::clamp(start.frequency + sign * sp.K_f * t, sp.f_min, sp.f_max), 0.05 * sp.K_f);
  EXPECT_NEAR(at_half_second.amplitude,
              std::clamp(start.amplitude + sign * sp.K_a * t, sp.amp_min, sp.amp_max),
              0.05 * sp.K_a);
}

// --- 3. Circular flight (Fig. 16): keeps circling the 30 m circle, banked into the turn, the
// tail twisted towards the turn and open while turning.
// The tail's twist steers the tail model only; with fixed-rate turning the circle is checked.
class Circling : public ::testing::TestWithParam<std::string> {};

TEST_P(Circling, KeepsCirclingBankedWithTheTailTwistedAndOpen) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const auto flight = make_flight(load_scenario(GetParam()));
  Simulation& sim = *flight;
  const bool tail_model = sim.world().turning == TurningModel::tail;
  const Species& sp = species_of(sim, sim.birds()[0]);
  double r_lo = 1e9, r_hi = 0, y_lo = 1e9, y_hi = -1e9;
  int frames = 0, banked_in = 0, turning = 0, twisted_in = 0, open_in_turn = 0;
  uint32_t reached_at_10s = 0;
  run(sim, 60.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    if (s.time() < 10.0) {
      reached_at_10s = b.targets_reached;
      return;
    }
    const double r = std::hypot(b.position.x, b.position.z);
    r_lo = std::min(r_lo, r), r_hi = std::max(r_hi, r);
    y_lo = std::min(y_lo, b.position.y), y_hi = std::max(y_hi, b.position.y);
    // The centre's side of the flight direction: right (+1) or left (-1).
    const double centre_side =
        (b.velocity.z * b.position.x - b.velocity.x * b.position.z) > 0 ? 1.0 : -1.0;
    ++frames;
    if (bank_angle(b.attitude) * centre_side > 0) ++banked_in;
    const Route& route = s.world().routes[b.route];
    const dvec3 goal = s.world().target_now[route.targets[b.target % route.targets.size()]];
    const Steering st = steer_towards(sp, b.attitude, b.position, b.velocity, goal, s.world().wind,
                                      sp.cruise_speed, false);
    if (std::fabs(st.heading_error) > sp.dead_band) {
      ++turning;
      if (b.tail_twist * centre_side > 0) ++twisted_in;
      if (tail_opening(sp, b.tail_bend, b.tail_twist) > sp.tail_min) ++open_in_turn;
    }
  });
  const uint32_t laps_targets = sim.birds()[0].targets_reached - reached_at_10s;
  RecordProperty("targets_in_50s", std::to_string(laps_targets));
  RecordProperty("radius_cm", std::to_string(r_lo) + ".." + std::to_string(r_hi));
  RecordProperty("height_cm", std::to_string(y_lo) + ".." + std::to_string(y_hi));
  EXPECT_GE(laps_targets, 24u) << "two laps of 12 targets in 50 s";
  EXPECT_GT(r_lo, 2500.0);
  EXPECT_LT(r_hi, 3500.0);
  EXPECT_GT(y_lo, 3000.0 - 300.0);
  EXPECT_LT(y_hi, 3000.0 + 300.0);
  EXPECT_GT(double(banked_in) / frames, 0.9) << "banked into the turn";
  ASSERT_GT(turning, 0);
  RecordProperty("twisted_towards_turn", std::to_string(double(twisted_in) / turning));
  RecordProperty("open_in_turn", std::to_string(double(open_in_turn) / turning));
  if (!tail_model) return;
  EXPECT_GT(double(twisted_in) / turning, 0.8) << "tail twisted towards the turn";
  EXPECT_GT(double(open_in_turn) / turning, 0.8) << "tail open while turning";
}

// Eq. 3: with fixed-rate turning the heading turns at R about the vertical, banked or not.
TEST(FixedRateTurning, HeadingTurnsAtTheStandardRate) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  Scenario scenario = straight_flight("starling", -1e5, 0.0);  // the target far behind
  scenario.world.turning = TurningModel::fixed_rate;
  const auto flight = make_flight(scenario);
  Simulation& sim = *flight;
  const Species& sp = species_of(sim, sim.birds()[0]);
  auto heading = [&] {
    const dvec3 head = sim.birds()[0].attitude * dvec3{1.0, 0.0, 0.0};
    return std::atan2(head.z, head.x);
  };
  run(sim, 1.0, [](Simulation&) {});  // banked into the turn by now
  const double before = heading(), bank = bank_angle(sim.birds()[0].attitude);
  run(sim, 1.5, [](Simulation&) {});
  const double turned = std::remainder(heading() - before, 2.0 * kPi);
  RecordProperty("bank_deg", std::to_string(degrees(bank)));
  EXPECT_GT(std::fabs(bank), radians(20.0));
  // The world-vertical rate is exactly R; the nose's heading also turns a little with the pitch
  // the tail gives the banked body (measured 0.95 R).
  RecordProperty("heading_rate_over_R", std::to_string(std::fabs(turned) / 0.5 / sp.turn_rate));
  EXPECT_NEAR(std::fabs(turned) / 0.5, sp.turn_rate, 0.1 * sp.turn_rate);
}

// --- 4. Ground effect (Fig. 17): descending to a target on the ground, the starling is held off
// it with k = 10 (it never touches down); without ground effect it meets the ground and touches
// down. The ground is solid: the body centre is never below it.
struct GroundPass {
  double lowest = 1e9;  // cm, body centre, every step
  bool touched_down = false;
};
GroundPass ground_pass(const std::string& scenario) {
  const auto flight = make_flight(load_scenario(scenario));
  Simulation& sim = *flight;
  GroundPass g;
  run_steps(sim, sim.scenario().duration, [&](Simulation& s) {
    g.lowest = std::min(g.lowest, s.birds()[0].position.y);
    g.touched_down = g.touched_down || s.birds()[0].mode == FlightMode::standing;
  });
  return g;
}

TEST(GroundEffect, HoldsTheStarlingOffTheGroundOnlyWhenOn) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const GroundPass with = ground_pass("fig17-ground-effect");
  const GroundPass without = ground_pass("fig17-no-ground-effect");
  RecordProperty("lowest_with_cm", std::to_string(with.lowest));
  RecordProperty("lowest_without_cm", std::to_string(without.lowest));
  EXPECT_GE(with.lowest, 0.0);
  EXPECT_FALSE(with.touched_down);
  EXPECT_TRUE(without.touched_down);
  EXPECT_GE(without.lowest, 0.0);
}

// The ground is solid: a starling diving at it from 3 m touches down, stands, and takes off again
// once rested and settled (its route goes on); its legs fold no further than its body resting
// on the ground, checked every step.
// The Fig. 17 starling diving at the ground from 3 m at 15 m/s through the air (60 degrees down,
// heading +x) in `wind`, its route on to a target 50 m on and 10 m up.
struct GroundDive {
  Scenario scenario;
  BirdState bird;
};
GroundDive ground_dive(const dvec3& wind) {
  GroundDive d{load_scenario("fig17-no-ground-effect"), BirdState{}};
  Scenario& s = d.scenario;
  s.world.targets[0].centre = {5000.0, 1000.0, 0.0};
  s.world.targets[0].radius = 200.0;
  s.world.target_now = {s.world.targets[0].centre};
  s.world.wind = wind;
  BirdState& b = d.bird;
  b.species = s.flocks[0].species;
  b.route = s.flocks[0].route;
  b.position = {0.0, 300.0, 0.0};
  b.attitude = glm::angleAxis(radians(-60.0), dvec3{0, 0, 1});
  b.velocity = wind + b.attitude * dvec3{1500.0, 0.0, 0.0};
  b.frequency = s.species[b.species].f_max;
  b.amplitude = s.species[b.species].amp_max;
  return d;
}

TEST(SolidGround, ADivingBirdTouchesDownAndTakesOffAgain) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const GroundDive dive = ground_dive(dvec3{0.0});
  const Scenario& s = dive.scenario;
  const Species& sp = s.species[dive.bird.species];
  const auto flight = make_flight_with(s, {dive.bird});
  Simulation& sim = *flight;
  double lowest = 1e9, touched_at = -1, settled_at = -1, took_off_at = -1;
  run_steps(sim, 3.0, [&](Simulation& x) {
    const BirdState& now = x.birds()[0];
    ASSERT_TRUE(std::isfinite(now.position.y));
    lowest = std::min(lowest, now.position.y);
    if (touched_at < 0 && now.mode == FlightMode::standing) touched_at = x.time();
    if (touched_at >= 0 && settled_at < 0 && now.landing_stage == LandingStage::none)
      settled_at = x.time();
    if (touched_at >= 0 && took_off_at < 0 && now.mode == FlightMode::taking_off)
      took_off_at = x.time();
  });
  RecordProperty("touched_down_s", std::to_string(touched_at));
  RecordProperty("took_off_s", std::to_string(took_off_at));
  // Its legs fold no further than its body resting on the ground (a hard touch-down).
  EXPECT_GE(lowest - 0.5 * sp.box_b, s.world.ground_height - 1e-6);
  ASSERT_GT(touched_at, 0.0) << "never touched down";
  // It takes off once rested and settled (issue 40): from 15 m/s it slides 1.1 m and turns level
  // from its dive at kSettleTurn, longer than its rest.
  RecordProperty("settled_s", std::to_string(settled_at));
  ASSERT_GT(settled_at, touched_at) << "never settled";
  EXPECT_NEAR(took_off_at - touched_at, std::max(kRestAfterTouchdown, settled_at - touched_at),
              2 * sim.scenario().dt);
}

// A bird takes off into the wind, and turns on its legs to face it once it has settled (issue 40:
// it was turned in one step, 180 degrees at once for a bird that touched down with the wind
// behind it). The starling above dives at the ground with a 5 m/s wind from behind: from its
// touch-down until it is airborne again its body turns at no more than kSettleTurn, checked every
// step; it takes off as soon as it faces into the wind (the turn left within a step's), which it
// does a turn's time (the angle left as it settled, at kSettleTurn) after it settled.
TEST(SolidGround, ABirdTurnsIntoTheWindOnItsLegsBeforeItTakesOff) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const GroundDive dive = ground_dive(dvec3{500.0, 0.0, 0.0});  // from behind it
  const Scenario& s = dive.scenario;
  const BirdState& b = dive.bird;
  const auto flight = make_flight_with(s, {b});
  Simulation& sim = *flight;
  const double dt = sim.scenario().dt;
  const glm::dquat into_wind = facing(-s.world.wind);
  double touched_at = -1, settled_at = -1, took_off_at = -1, left_at_settle = 0, fastest = 0;
  glm::dquat before = b.attitude;
  run_steps(sim, 6.0, [&](Simulation& x) {
    const BirdState& now = x.birds()[0];
    const bool on_legs = touched_at >= 0;  // since a step before this one
    if (touched_at < 0 && now.mode == FlightMode::standing) touched_at = x.time();
    if (touched_at >= 0 && settled_at < 0 && now.landing_stage == LandingStage::none) {
      settled_at = x.time();
      left_at_settle = turn_angle(now.attitude, into_wind);
    }
    if (on_legs && took_off_at < 0) {
      // The step's turn from its rotation's axis part: the shaders' float attitudes resolve a
      // step's 0.02 degrees there, not in w (turn_angle's).
      const glm::dquat r = now.attitude * glm::conjugate(before);
      const double turn = 2.0 * std::atan2(glm::length(dvec3{r.x, r.y, r.z}), std::fabs(r.w));
      fastest = std::max(fastest, turn / dt);
      if (now.mode == FlightMode::taking_off) {
        took_off_at = x.time();
        EXPECT_LT(turn_angle(now.attitude, into_wind), kSettledAngle) << "it takes off into it";
      }
    }
    before = now.attitude;
  });
  RecordProperty("angle_left_at_settle_deg", std::to_string(degrees(left_at_settle)));
  RecordProperty("fastest_turn_deg_s", std::to_string(degrees(fastest)));
  ASSERT_GT(settled_at, touched_at) << "never settled";
  ASSERT_GT(took_off_at, settled_at) << "never took off";
  EXPECT_GT(left_at_settle, radians(150.0)) << "the wind was behind it";
  EXPECT_LE(fastest, kSettleTurn + 1e-6 / dt) << "rad/s (1e-6 rad a step: float attitudes)";
  EXPECT_NEAR(took_off_at - settled_at, left_at_settle / kSettleTurn, 2 * dt);
}

// Issue 16: eq. 15's k G m / h has no bound as h -> 0; a bird spawned at the ground, or 1e-6 m
// above it, was thrown up at 1.5 km/s or became NaN. Evaluated no nearer than the body's half
// height (ground_effect_floor), the Fig. 17 starling spawned there flies the whole flight (every
// step) finite, never below the ground, and never faster than it could: its fastest airspeed
// command, its start speed, and what eq. 15 gives over its whole range from the floor,
// integral of k G / h dh = k G ln(l / floor), as speed sqrt(2 k G ln(l / floor)).
class GroundSpawn : public ::testing::TestWithParam<double> {};

TEST_P(GroundSpawn, FliesFiniteNeverBelowTheGroundNorFasterThanItCould) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  Scenario s = load_scenario("fig17-ground-effect");
  s.flocks[0].spawn_centre.y = s.world.ground_height + GetParam();
  const auto flight = make_flight(s);
  Simulation& sim = *flight;
  const Species& sp = species_of(sim, sim.birds()[0]);
  const double start_speed = glm::length(sim.birds()[0].velocity);
  const double from_ground =
      std::sqrt(2.0 * sp.ground_k * kGravity * std::log(sp.wing_length / ground_effect_floor(sp)));
  const double bound = std::max(sp.max_speed, start_speed) + from_ground;
  double lowest = 1e9, fastest = 0.0;
  run_steps(sim, s.duration, [&](Simulation& x) {
    const BirdState& now = x.birds()[0];
    ASSERT_TRUE(finite(now)) << "at " << x.time() << " s";
    lowest = std::min(lowest, now.position.y);
    fastest = std::max(fastest, glm::length(now.velocity));
  });
  RecordProperty("lowest_cm", std::to_string(lowest));
  RecordProperty("fastest_cm_s", std::to_string(fastest));
  EXPECT_GE(lowest, s.world.ground_height);
  EXPECT_LE(fastest, bound);
  // Settled: it reached its target on the ground and flies on at its cruise height.
  EXPECT_EQ(sim.birds()[0].targets_reached, 1u);
  EXPECT_EQ(sim.birds()[0].mode, FlightMode::flying);
}

INSTANTIATE_TEST_SUITE_P(AtAndJustAbove, GroundSpawn, ::testing::Values(0.0, 1e-4),
                         [](const ::testing::TestParamInfo<double>& i) {
                           return i.param == 0.0 ? std::string("at_the_ground")
                                                 : std::string("1e_6_m_above");
                         });

// --- NaN quarantine (issue 16): a bird whose step is not finite is frozen at its last finite
// state, and the rest fly on as they would without it.

// Every field of two states the same.
bool same_state(const BirdState& a, const BirdState& b) {
  return true
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) &&a.name == b.name
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
      ;
}

// Fig. 17's starling and a second one 10 m to its side whose species has a NaN ground-effect
// coefficient (make_flock_non_finite): a wing length above the ground its step is not finite.
Scenario doomed_descent() {
  Scenario s = load_scenario("fig17-ground-effect");
  s.duration = 8.0;
  Flock doomed = s.flocks[0];
  doomed.name = "doomed";
  doomed.spawn_centre.z += 1000.0;
  s.flocks.push_back(doomed);
  make_flock_non_finite(s, "doomed");
  return s;
}

TEST(NanQuarantine, FreezesTheBirdAtItsLastFiniteStateWhileTheOtherFliesOn) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const Scenario s = doomed_descent();
  Scenario without = s;
  without.flocks.pop_back();
  const auto flight = make_flight(s);
  const auto alone = make_flight(without);
  Simulation& sim = *flight;
  const Species& sp = species_of(sim, sim.birds()[1]);
  BirdState last = sim.birds()[1];
  double quarantined_in = -1.0;  // the start of the step that was not finite
  uint64_t quarantined_step = 0;
  run_steps(sim, s.duration, [&](Simulation& x) {
    alone->step(1);
    const BirdState& b = x.birds()[1];
    ASSERT_TRUE(all_finite(b) && all_finite(x.birds()[0])) << "at " << x.time() << " s";
    ASSERT_TRUE(same_state(x.birds()[0], alone->birds()[0]))
        << "the other bird, at " << x.time() << " s";
    if (b.mode != FlightMode::quarantined) {
      last = b;
      return;
    }
    if (quarantined_in < 0.0) {
      quarantined_in = x.time() - x.scenario().dt;
      quarantined_step = x.steps() - 1;
    }
    EXPECT_EQ(b.quarantined_step, quarantined_step);  // the step, exact on both backends
    BirdState frozen = last;
    frozen.mode = FlightMode::quarantined;
    frozen.quarantined_step = b.quarantined_step;
    ASSERT_TRUE(same_state(b, frozen))
        << "not frozen at its last finite state, at " << x.time() << " s";
  });
  RecordProperty("quarantined_at_s", std::to_string(quarantined_in));
  RecordProperty("last_height_cm", std::to_string(last.position.y));
  ASSERT_GT(quarantined_in, 1.0) << "never quarantined, or at once";
  EXPECT_LT(last.position.y - s.world.ground_height, sp.wing_length);  // where eq. 15 acts
  EXPECT_GT(sim.time() - quarantined_in, 2.0);  // and the flight went on well after
}

// A flock of 20 murmuration starlings, one of them (5) of a species with a NaN lift coefficient:
// quarantined in its first step, frozen at its spawn state; its flock, which saw it for its first
// reaction time, flies on finite.
TEST(NanQuarantine, AFlockFliesOnFiniteAroundAQuarantinedBird) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  Scenario s = load_scenario("murmuration");
  std::vector<BirdState> birds = spawn_birds(s, 20);
  Species doomed = s.species[birds[5].species];
  doomed.Cl_max = std::numeric_limits<double>::quiet_NaN();
  birds[5].species = static_cast<uint32_t>(s.species.size());
  s.species.push_back(doomed);
  const auto flight = make_flight_with(s, birds);
  Simulation& sim = *flight;
  const BirdState spawned = sim.birds()[5];
  std::optional<BirdState> frozen;  // as the backend keeps it (the device: in float)
  uint32_t seen = 0;
  run(sim, 10.0, [&](Simulation& x) {
    for (size_t i = 0; i < x.birds().size(); ++i) {
      const BirdState& b = x.birds()[i];
      ASSERT_TRUE(all_finite(b)) << "bird " << i << " at " << x.time() << " s";
      if (i != 5) {
        ASSERT_NE(b.mode, FlightMode::quarantined) << "bird " << i << " at " << x.time() << " s";
      }
    }
    const BirdState& b = x.birds()[5];
    if (!frozen) {
      ASSERT_EQ(b.mode, FlightMode::quarantined);
      EXPECT_EQ(b.quarantined_step, 0u);
      EXPECT_LT(glm::distance(b.position, spawned.position), 1e-3);
      EXPECT_LT(glm::distance(b.velocity, spawned.velocity), 1e-3);
      EXPECT_EQ(float(b.phase), float(spawned.phase));  // not stepped (the device keeps floats)
      frozen = b;
    }
    ASSERT_TRUE(same_state(b, *frozen)) << "at " << x.time() << " s";
    if (const auto* p = x.snapshot().perception)
      for (const Perception& q : *p) seen += q.neighbours;
  });
  EXPECT_GT(seen, 0u) << "the flock saw one another";
}

// --- 5. Take-off (Figs. 19, 20): higher at 0.3 s and 0.7 s with the leg force than without.
struct Heights {
  double at_03 = 0, at_07 = 0;
};
Heights takeoff_heights(const std::string& scenario) {
  const auto flight = make_flight(load_scenario(scenario));
  Simulation& sim = *flight;
  Heights h;
  run_steps(sim, 0.3, [](Simulation&) {});
  h.at_03 = sim.birds()[0].position.y;
  run_steps(sim, 0.7, [](Simulation&) {});
  h.at_07 = sim.birds()[0].position.y;
  return h;
}

TEST(TakeOff, LegForceGivesAQuickerAscent) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const Heights legs = takeoff_heights("fig20-takeoff-legs");
  const Heights none = takeoff_heights("fig19-takeoff-no-legs");
  RecordProperty("with_legs_cm", std::to_string(legs.at_03) + ", " + std::to_string(legs.at_07));
  RecordProperty("without_cm", std::to_string(none.at_03) + ", " + std::to_string(none.at_07));
  EXPECT_GT(legs.at_03, none.at_03);
  EXPECT_GT(legs.at_07, none.at_07);
}

TEST(TakeOff, CrouchesBeforeThePush) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const auto flight = make_flight(load_scenario("fig20-takeoff-legs"));
  Simulation& sim = *flight;
  const Species& sp = species_of(sim, sim.birds()[0]);
  const double standing = sim.birds()[0].position.y;
  run_steps(sim, 0.95 * sp.crouch_time, [](Simulation&) {});
  // Crouched in proportion to its time on the legs before this step (step.cpp: stand_on_legs), at
  // the step that ends at or just after 0.95 crouch_time.
  const double dt = sim.scenario().dt;
  const double crouched = std::min((sim.time() - dt) / sp.crouch_time, 1.0);
  EXPECT_GE(crouched, 0.8);  // late in the crouch, at any step the study flies
  EXPECT_NEAR(sim.birds()[0].position.y, standing - crouched * sp.crouch_depth,
              0.01 * sp.crouch_depth);
  EXPECT_EQ(sim.birds()[0].mode, FlightMode::taking_off);
}

// Issue 10: what turns the bird (docs/MODEL.md "What we added, and why"). The Fig. 16 eagle with
// its tail twist and without it (rot_max = 0): both circle, banked, at the same radius, so the bank
// turns it; the figures (turn rate, sideslip, radius) go to docs/MODEL.md.
struct CircleFigures {
  uint32_t targets = 0;           // in 50 s after the first 10
  double r_lo = 1e9, r_hi = 0.0;  // cm
  double turn_rate = 0.0;         // mean heading rate, rad/s
  double sideslip = 0.0;          // mean |angle from the head to the air velocity|, rad
};
CircleFigures circle_figures(double rot_max) {
  Scenario scenario = load_scenario("fig16-circling-eagle");
  scenario.species[0].rot_max = rot_max;
  const auto flight = make_flight(scenario);
  Simulation& sim = *flight;
  CircleFigures f;
  uint32_t at_10 = 0;
  int frames = 0;
  double last_heading = 0.0;
  run(sim, 60.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    const double heading = std::atan2(b.velocity.z, b.velocity.x);
    if (s.time() < 10.0) {
      at_10 = b.targets_reached;
      last_heading = heading;
      return;
    }
    const dvec3 head = b.attitude * dvec3{1.0, 0.0, 0.0};
    const dvec3 air = b.velocity - s.world().wind;
    f.sideslip +=
        std::fabs(std::atan2(-head.z * air.x + head.x * air.z, head.x * air.x + head.z * air.z));
    f.turn_rate += std::remainder(heading - last_heading, 2.0 * kPi) /
                   (s.scenario().dt * s.scenario().steps_per_frame);
    last_heading = heading;
    const double r = std::hypot(b.position.x, b.position.z);
    f.r_lo = std::min(f.r_lo, r);
    f.r_hi = std::max(f.r_hi, r);
    ++frames;
  });
  f.targets = sim.birds()[0].targets_reached - at_10;
  f.turn_rate /= frames;
  f.sideslip /= frames;
  return f;
}

TEST(TurnAblation, TheBankTurnsTheBirdWithOrWithoutTheTailTwist) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const CircleFigures with =
      circle_figures(load_scenario("fig16-circling-eagle").species[0].rot_max);
  const CircleFigures without = circle_figures(0.0);
  for (const auto& [name, f] :
       {std::pair{"with_twist", with}, std::pair{"without_twist", without}}) {
    RecordProperty(std::string(name) + "_targets_in_50s", std::to_string(f.targets));
    RecordProperty(std::string(name) + "_radius_cm",
                   std::to_string(f.r_lo) + ".." + std::to_string(f.r_hi));
    RecordProperty(std::string(name) + "_turn_rate_deg_s", std::to_string(degrees(f.turn_rate)));
    RecordProperty(std::string(name) + "_sideslip_deg", std::to_string(degrees(f.sideslip)));
  }
  for (const CircleFigures& f : {with, without}) {
    EXPECT_GE(f.targets, 24u);
    EXPECT_GT(f.r_lo, 2500.0);
    EXPECT_LT(f.r_hi, 3500.0);
  }
  EXPECT_NEAR(without.turn_rate, with.turn_rate, 0.1 * std::fabs(with.turn_rate))
      << "the same turn";
  // Both turns are coordinated: the head within a few degrees of the airflow. Which has less
  // sideslip is not a property of the model: it turns on the step (docs/convergence.md: with the
  // twist 4.2-4.8 degrees, without it 4.1-5.3, over the steps of 0.5 to 10 ms).
  for (const CircleFigures& f : {with, without})
    EXPECT_LT(degrees(f.sideslip), 8.0) << "a coordinated turn";
}

// Issue 10: the take-off climbs out to its route. Followed for 5 s: never below the ground, never
// pitched past 60 degrees nor banked past bank_max, never NaN, and flying clear of the ground.
class ClimbOut : public ::testing::TestWithParam<std::string> {};

TEST_P(ClimbOut, FollowedForFiveSecondsItNeverLoops) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const auto flight = make_flight(load_scenario(GetParam()));
  Simulation& sim = *flight;
  const Species& sp = species_of(sim, sim.birds()[0]);
  const double ground = sim.world().ground_height;
  double lowest = 1e9, steepest = 0.0, deepest = 0.0;
  bool all_finite = true;
  run(sim, 5.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    all_finite = all_finite && finite(b);
    lowest = std::min(lowest, b.position.y - ground);
    steepest = std::max(steepest, std::fabs(pitch_angle(b.attitude)));
    deepest = std::max(deepest, std::fabs(bank_angle(b.attitude)));
  });
  const BirdState& b = sim.birds()[0];
  RecordProperty("steepest_pitch_deg", std::to_string(degrees(steepest)));
  RecordProperty("height_at_5s_cm", std::to_string(b.position.y - ground));
  EXPECT_TRUE(all_finite);
  EXPECT_GE(lowest, sp.stand_height - sp.crouch_depth - 1e-3);
  EXPECT_LT(steepest, radians(60.0));
  EXPECT_LE(deepest, sp.bank_max + radians(0.5));
  EXPECT_EQ(b.mode, FlightMode::flying);
  EXPECT_GT(b.position.y - ground, 300.0) << "clear of the ground after 5 s";
}

// A bird takes off into the wind (faster than half touchdown_speed): a flock set down standing
// with a 5 m/s wind behind it or from its side stands facing the wind, and climbs out as in still
// air. Followed for 5 s. (A bird that stands turned away turns on its legs first:
// SolidGround.ABirdTurnsIntoTheWindOnItsLegsBeforeItTakesOff.)
TEST(TakeOff, FacesTheWindAndClimbsOut) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  for (const dvec3 wind : {dvec3{500.0, 0.0, 0.0}, dvec3{0.0, 0.0, -500.0}}) {
    Scenario scenario = load_scenario("fig20-takeoff-legs");  // facing +x
    scenario.world.wind = wind;
    const auto flight = make_flight(scenario);
    Simulation& sim = *flight;
    const Species& sp = species_of(sim, sim.birds()[0]);
    double lowest = 1e9, steepest = 0.0, facing_off = -1.0;
    bool all_finite = true;
    run(sim, 5.0, [&](Simulation& s) {
      const BirdState& b = s.birds()[0];
      all_finite = all_finite && finite(b);
      lowest = std::min(lowest, b.position.y - s.world().ground_height);
      steepest = std::max(steepest, std::fabs(pitch_angle(b.attitude)));
      if (facing_off < 0.0 && b.mode == FlightMode::taking_off) {
        const dvec3 head = b.attitude * dvec3{1.0, 0.0, 0.0};
        facing_off = std::acos(
            std::clamp(glm::dot(glm::normalize(head), -wind / glm::length(wind)), -1.0, 1.0));
      }
    });
    const BirdState& b = sim.birds()[0];
    const std::string from = wind.x > 0.0 ? "behind" : "the side";
    RecordProperty(
        "wind_from_" + std::string(wind.x > 0.0 ? "behind" : "side") + "_steepest_pitch_deg",
        std::to_string(degrees(steepest)));
    EXPECT_TRUE(all_finite) << from;
    EXPECT_GE(facing_off, 0.0) << from << ": never took off";
    EXPECT_LT(facing_off, radians(1.0)) << from << ": head off the wind's opposite at take-off";
    EXPECT_GE(lowest, sp.stand_height - sp.crouch_depth - 1e-3) << from;
    EXPECT_LT(steepest, radians(60.0)) << from;
    EXPECT_EQ(b.mode, FlightMode::flying) << from;
    EXPECT_GT(b.position.y - sim.world().ground_height, 300.0)
        << from << ": clear of the ground after 5 s";
  }
}

// Issue 10: a commanded airspeed is held within 0.5 m/s in level flight (each second's mean, from
// 15 s to 30 s), by the wingbeat and the pitch; the height stays within 2 m. At each species'
// min_speed, cruise_speed and max_speed.
struct AirspeedCase {
  const char* species;
  double airspeed;  // cm/s
};
class AirspeedHold : public ::testing::TestWithParam<AirspeedCase> {};

TEST_P(AirspeedHold, HoldsTheCommandedAirspeedInLevelFlight) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const Scenario scenario = straight_flight(GetParam().species, 1e7, 0.0);
  CpuSimulation start(scenario);
  std::vector<BirdState> birds = start.state();
  birds[0].airspeed = GetParam().airspeed;
  const auto flight = make_flight_with(scenario, birds);
  Simulation& sim = *flight;
  double sum = 0.0, worst = 0.0, height_off = 0.0;
  int frames = 0;
  run(sim, 30.0, [&](Simulation& s) {
    if (s.time() < 15.0) return;
    const BirdState& b = s.birds()[0];
    sum += glm::length(b.velocity - s.world().wind);
    height_off = std::max(height_off, std::fabs(b.position.y - 3000.0));
    if (++frames % 33 == 0) {  // about 1 s of frames
      worst = std::max(worst, std::fabs(sum / 33.0 - GetParam().airspeed));
      sum = 0.0;
      frames = 0;
    }
  });
  RecordProperty("worst_second_off_cm_s", std::to_string(worst));
  RecordProperty("height_off_cm", std::to_string(height_off));
  EXPECT_LE(worst, 50.0);
  EXPECT_LE(height_off, 200.0);
}

// Issue 10: the bank never passes bank_max, also turning hard in a crosswind (60.6 degrees was
// measured in a 5 m/s crosswind before the bank followed its command through the body's rates).
TEST(Turning, NeverBanksPastBankMax) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  Scenario scenario = straight_flight("starling", -30000.0, 0.0);  // the target behind it
  scenario.world.wind = dvec3{0.0, 0.0, 500.0};
  const auto flight = make_flight(scenario);
  Simulation& sim = *flight;
  const Species& sp = species_of(sim, sim.birds()[0]);
  double deepest = 0.0;
  run(sim, 30.0, [&](Simulation& s) {
    deepest = std::max(deepest, std::fabs(bank_angle(s.birds()[0].attitude)));
  });
  RecordProperty("deepest_bank_deg", std::to_string(degrees(deepest)));
  EXPECT_GT(deepest, sp.bank_max - radians(1.0)) << "it turns at full bank";
  EXPECT_LE(deepest, sp.bank_max + radians(0.5));
}

// A starling on its way to a target 2 km ahead along x in `wind`, compensating for the drift by
// `compensation`, flown for `seconds`: how far (cm) it was carried off the line (the x axis) after
// the first 10 s of turning in, until it got there; the flight in `sim_out`.
double farthest_off_line(const dvec3& wind, double compensation, double seconds,
                         std::unique_ptr<Simulation>* sim_out = nullptr) {
  Scenario scenario = straight_flight("starling", 200000.0, 0.0);
  scenario.world.wind = wind;
  for (Species& sp : scenario.species) sp.drift_compensation = compensation;
  std::unique_ptr<Simulation> flight = make_flight(scenario);
  double farthest = 0.0;
  run(*flight, seconds, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    EXPECT_TRUE(is_finite(b));
    if (s.time() > 10.0 && b.targets_reached == 0)
      farthest = std::max(farthest, std::fabs(b.position.z));
  });
  if (sim_out) *sim_out = std::move(flight);
  return farthest;
}

// Issue 39: in a crosswind with a tailwind share the bird holds its track to a target 2 km ahead
// (track_aim). Aimed for cruise speed over the ground while flying faster than that through the
// air, it pointed too far into the wind and drifted upwind: 27 m off the line after 30 s and 54 m
// after 60 s in this wind (4 m/s across, 3 m/s behind); 2.5 and 5.1 m holding its track.
TEST(Crosswind, HoldsItsTrackToTheTarget) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  std::unique_ptr<Simulation> sim;
  const double farthest = farthest_off_line(dvec3{300.0, 0.0, 400.0}, 1.0, 60.0, &sim);
  RecordProperty("farthest_off_line_cm", std::to_string(farthest));
  EXPECT_LE(farthest, 1000.0) << "10 m";
  EXPECT_GT(sim->birds()[0].position.x, 60.0 * 1000.0) << "it makes more than cruise speed";
}

// Issue 39: drift_compensation, the share of the wind's drift a bird cancels (migrants are
// measured anywhere from full drift to full compensation). In 4 m/s straight across a 2 km leg,
// the farther from full compensation, the farther the bird is carried off the line on its way
// (measured: 24, 170 and 292 m at 1, 0.5 and 0; in full, what is left is the heading's dead band:
// it settles 0.9 degrees short of the crab, a 0.17 m/s drift that the bearing of a target 2 km
// away corrects only near it); it still gets there, its heading turned back towards the target.
TEST(Crosswind, DriftGrowsAsCompensationFalls) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const dvec3 across{0.0, 0.0, 400.0};
  double farthest[3];
  const double compensation[3] = {1.0, 0.5, 0.0};
  for (int k = 0; k < 3; ++k) {
    std::unique_ptr<Simulation> sim;
    farthest[k] = farthest_off_line(across, compensation[k], 300.0, &sim);
    EXPECT_EQ(sim->birds()[0].targets_reached, 1u) << compensation[k] << ": it still gets there";
  }
  RecordProperty("farthest_off_line_cm_full_half_none", std::to_string(farthest[0]) + " " +
                                                            std::to_string(farthest[1]) + " " +
                                                            std::to_string(farthest[2]));
  EXPECT_GT(farthest[1], 5.0 * farthest[0]);
  EXPECT_GT(farthest[2], 1.5 * farthest[1]);
}

// Issue 10: a 90-degree corner is turned as tightly with the next target 2 km away as with it
// 50 m away (the pure-pursuit bank alone shrank with distance: about 200 m of overshoot).
double corner_overshoot(double next_distance) {
  const std::string toml = R"(
[simulation]
duration = 60.0
[[targets]]
name = "corner"
centre = [20000.0, 3000.0, 0.0]
radius = 300.0
[[targets]]
name = "next"
centre = [20000.0, 3000.0, )" +
                           std::to_string(next_distance) + R"(]
radius = 300.0
[[routes]]
name = "r"
targets = ["corner", "next"]
[[flocks]]
name = "f"
species = "starling"
route = "r"
centre = [0.0, 3000.0, 0.0]
speed = 1000.0
random_phase = false
)";
  const auto flight = make_flight(parse_scenario(toml, "corner.toml"));
  Simulation& sim = *flight;
  double beyond = 0.0;
  run(sim, 40.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    if (b.targets_reached >= 1) beyond = std::max(beyond, b.position.x - 20000.0);
  });
  EXPECT_GE(sim.birds()[0].targets_reached, 1u);
  return beyond;
}

TEST(Turning, ACornerIsTurnedAlikeWhereverTheNextTargetIs) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const double far = corner_overshoot(200000.0);
  const double near = corner_overshoot(5000.0);
  RecordProperty("overshoot_next_2km_cm", std::to_string(far));
  RecordProperty("overshoot_next_50m_cm", std::to_string(near));
  EXPECT_LT(std::fabs(far - near), 1020.0) << "within the radius of a turn at bank_max and 10 m/s";
  // The circle at bank_max and 10 m/s has a radius of 10.2 m; rolling in takes about 1 s more.
  EXPECT_LT(far, 3000.0);
}

// --- 6. Branch landing (Fig. 18): with path control the approach over the last metre is within
// 20 degrees of perpendicular to the branch and the bird ends perched; the direct method comes in
// at the angle it happened to come from.
struct Landing {
  bool perched = false;
  double approach_off_perpendicular = 0;  // degrees
};
Landing land(const Scenario& scenario) {
  const auto flight = make_flight(scenario);
  Simulation& sim = *flight;
  const Branch& branch = sim.world().branches[0];
  std::vector<dvec3> track;
  Landing result;
  run(sim, sim.scenario().duration, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    if (b.mode != FlightMode::perched) track.push_back(b.position);
    result.perched = b.mode == FlightMode::perched;
  });
  // The horizontal direction of flight over the last metre of the track before perching.
  const dvec3 end = track.empty() ? sim.birds()[0].position : track.back();
  dvec3 from = end;
  double length = 0.0;
  for (size_t i = track.size(); i-- > 1 && length < 100.0;) {
    length += std::hypot(track[i].x - track[i - 1].x, track[i].z - track[i - 1].z);
    from = track[i - 1];
  }
  const dvec3 d = glm::normalize(dvec3{end.x - from.x, 0.0, end.z - from.z});
  const double along = std::fabs(glm::dot(d, branch.direction));
  result.approach_off_perpendicular = degrees(std::asin(std::min(1.0, along)));
  return result;
}

// A starling at `start` flying along `heading` (degrees) to land on the Fig. 18 branch.
Scenario landing_from(const dvec3& start, double heading,
                      const std::string& scenario = "fig18-branch-path-control") {
  Scenario s = load_scenario(scenario);
  s.flocks[0].spawn_centre = start;
  s.flocks[0].heading = radians(heading);
  return s;
}

TEST(BranchLanding, PathControlComesInPerpendicularAndPerches) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const Landing controlled = land(load_scenario("fig18-branch-path-control"));
  RecordProperty("path_control_off_perpendicular_deg",
                 std::to_string(controlled.approach_off_perpendicular));
  EXPECT_TRUE(controlled.perched);
  EXPECT_LT(controlled.approach_off_perpendicular, 20.0);
  // The direct method keeps the angle it comes from: from a start whose straight line to the
  // branch is 59 degrees off its perpendicular (the Fig. 18 start's is 8 degrees off, which a bird
  // turning onto its goal flies in along whatever the method).
  const Landing direct = land(landing_from(dvec3{0.0, 800.0, 4000.0}, 0.0, "fig18-branch-direct"));
  RecordProperty("direct_59_off_perpendicular_deg",
                 std::to_string(direct.approach_off_perpendicular));
  EXPECT_TRUE(direct.perched);
  EXPECT_GT(direct.approach_off_perpendicular, 20.0) << "the direct method keeps its angle";
}

// Issue 40: Fig. 18 with path control and straight in, on both backends. The centre moves no more
// in the frame of the grip than the bird flies (plus 1 cm); after it the speed falls at no more
// than 30 m/s^2 and the body turns at no more than 90 degrees/s, over each 30 ms frame. Before, it
// was put on the branch in one step, 68 cm away.
std::vector<Touchdown> fig18_touchdowns(const char* name) {
  const auto flight = make_flight(load_scenario(name));
  Simulation& sim = *flight;
  TouchdownWatch watch;
  run(sim, sim.scenario().duration, [&](Simulation& s) { watch.sample(s.time(), s.birds()[0]); });
  for (const Touchdown& d : watch.touchdowns())
    std::printf(
        "%s: jump %.1f cm (body %.1f deg), mean speed %.2f m/s over %.3f s, speed falls "
        "%.1f m/s2, turns %.0f deg/s, feet %.1f cm from the branch point, %zu go-rounds\n",
        name, d.jump, degrees(d.turn_jump), d.mean_speed / 100.0, d.window, d.speed_fall / 100.0,
        degrees(d.turn_rate), d.reach, watch.go_rounds());
  return watch.touchdowns();
}

TEST(BranchLanding, TheGripEndsTheFlightWithoutAJump) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  for (const char* name : {"fig18-branch-path-control", "fig18-branch-direct"}) {
    const std::vector<Touchdown> touchdowns = fig18_touchdowns(name);
    ASSERT_EQ(touchdowns.size(), 1u) << name;
    const Touchdown& d = touchdowns[0];
    RecordProperty(std::string(name) + "_mean_speed_m_s", std::to_string(d.mean_speed / 100.0));
    RecordProperty(std::string(name) + "_reach_cm", std::to_string(d.reach));
    EXPECT_TRUE(d.on_branch) << name;
    EXPECT_LE(d.jump, 1.0) << name;
    EXPECT_LE(d.speed_fall, 3000.0) << name;
    EXPECT_LE(d.turn_rate, radians(90.0)) << name;
    EXPECT_LE(d.turn_jump, radians(90.0) * kFrameSeconds) << name;
  }
}

// Issue 40: the feet, under the centre as when the bird stands, meet the branch within a few
// centimetres as it grips (it hovers onto the branch point: Species::hover_final), at a mean speed
// over the ground of at most touchdown_speed over the wingbeat (or 100 ms) before. Before, its
// centre was 63 and 83 cm from the perch point and it gripped at the first instant its speed
// dipped to touchdown_speed, at a mean of 2.45 and 2.46 m/s.
TEST(BranchLanding, TheFeetMeetTheBranchPointSlowly) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const Species sp = starling();
  for (const char* name : {"fig18-branch-path-control", "fig18-branch-direct"}) {
    const std::vector<Touchdown> touchdowns = fig18_touchdowns(name);
    ASSERT_EQ(touchdowns.size(), 1u) << name;
    EXPECT_LE(touchdowns[0].reach, 5.0) << name;
    EXPECT_LE(touchdowns[0].mean_speed, sp.touchdown_speed) << name;
  }
}

// Issue 40: a species that hovers onto the branch point does so from every side: the envelope's 16
// landings in calm air (the branch 30 and 60 m off, 0-180 degrees off its heading, 2 m below),
// flown whole and judged as the envelope judges them, each perches on its first pass, its feet
// within kGripReach stand_height of the point at a mean speed over its last wingbeat of at most
// touchdown_speed, with no jump, and settles within issue 40's limits; the judge holds every
// flight above the ground and within the envelope's limits until it perches.
void expect_calm_landings_on_the_point(const Species& s) {
  ASSERT_TRUE(hovers(s)) << s.name;
  std::vector<EnvelopeCase> cases;
  for (const EnvelopeCase& c : envelope_cases())
    if (c.kind == EnvelopeCase::Kind::landing && c.crosswind == 0.0) cases.push_back(c);
  ASSERT_EQ(cases.size(), 16u);
  const EnvelopeFlight flight = envelope_flight(s, cases, flight_step(Scenario{}).dt);
  std::unique_ptr<Simulation> sim = make_flight_with(flight.scenario, flight.birds);
  std::vector<EnvelopeResult> results(cases.size());
  std::vector<TouchdownWatch> watches(cases.size(), TouchdownWatch(kFrameSeconds));
  std::vector<bool> judged(cases.size(), false);
  for (size_t i = 0; i < cases.size(); ++i) results[i].c = cases[i];
  auto done = [&] {
    for (size_t i = 0; i < cases.size(); ++i)
      if (!judged[i] || !watches[i].settled(sim->time())) return false;
    return true;
  };
  while (!done() && sim->time() < flight.longest + kSettleWatch + 1.0) {
    sim->step(flight.scenario.steps_per_frame);
    for (size_t i = 0; i < cases.size(); ++i) {
      const BirdState b = sim->birds()[i];
      watches[i].sample(sim->time(), b);
      if (!judged[i])
        judged[i] =
            judge_envelope(results[i], b, s, sim->time(), flight.scenario.world.ground_height);
      // Followed until it has settled on the branch: never NaN.
      ASSERT_TRUE(is_finite(b)) << cases[i].describe();
    }
  }
  EXPECT_TRUE(done()) << "every bird judged and settled";
  double reach = 0.0, mean = 0.0;
  for (size_t i = 0; i < cases.size(); ++i) {
    EnvelopeResult& r = results[i];
    EXPECT_EQ(r.outcome, Outcome::reached) << r.c.describe() << ": " << name(r.outcome);
    EXPECT_EQ(watches[i].go_rounds(), 0u) << r.c.describe();
    ASSERT_FALSE(watches[i].touchdowns().empty()) << r.c.describe();
    r.touchdown = watches[i].touchdowns()[0];
    EXPECT_TRUE(r.touchdown->on_branch) << r.c.describe();
    expect_smooth_touchdown(r, s);
    reach = std::max(reach, r.touchdown->reach);
    mean = std::max(mean, r.touchdown->mean_speed);
  }
  ::testing::Test::RecordProperty("worst_reach_cm", std::to_string(reach));
  ::testing::Test::RecordProperty("worst_mean_speed_m_s", std::to_string(mean / 100.0));
}

// The real starling (80 g; its feet reach 2 cm). With the paper starling's final alone 0-2 of them
// perched within 60 s (from 45-135 degrees off it passed 12 cm wide of the point):
// Species::final_track_lead and final_beats_faster.
TEST(BranchLanding, TheRealStarlingHoversOntoThePointFromEverySide) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  expect_calm_landings_on_the_point(european_starling());
}

// The eagle (2 kg; its feet reach 10 cm), braking with its wings as well as its pitch. Holding its
// speed by its pitch alone none of them perched within 60 s (2-3 go-rounds each: it passed the
// point at 3-3.5 m/s); flaring, it gripped up to 2 m from the point: Species::hover_incidence.
TEST(BranchLanding, TheEagleHoversOntoThePointFromEverySide) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  expect_calm_landings_on_the_point(eagle());
}

// A bird with stubs for wings, flying at 3 m/s with its feet 3 cm above the ground, comes down on
// it at once (issue 40): it stands where its legs meet the ground, no move beyond its own flight,
// and slides to a stop and settles there, its speed falling at no more than 30 m/s^2 and its body
// turning at no more than 90 degrees/s over each 30 ms frame; then it tries to take off again.
// Before, it was put on its legs, still and level, in one step: its speed fell at 100 m/s^2.
TEST(TouchDown, OnTheGroundWithoutAJump) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const auto flight = make_flight(
      parse_scenario(std::string("[simulation]\nduration = 3.0\n") + testing::kStubWingedWorld + R"(
[[flocks]]
species = "stub-winged"
route = "r"
centre = [0.0, 15.0, 0.0]
speed = 300.0
random_phase = false
)",
                     "hop.toml"));
  Simulation& sim = *flight;
  TouchdownWatch watch;
  double lowest = 1e9;
  bool settled = false;
  run(sim, 3.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    watch.sample(s.time(), b);
    lowest = std::min(lowest, b.position.y);
    settled |= b.mode == FlightMode::standing && b.landing_stage == LandingStage::none &&
               !watch.touchdowns().empty();
  });
  ASSERT_GE(watch.touchdowns().size(), 1u) << "it never came down";
  const Touchdown& d = watch.touchdowns()[0];
  RecordProperty("jump_cm", std::to_string(d.jump));
  RecordProperty("speed_fall_m_s2", std::to_string(d.speed_fall / 100.0));
  RecordProperty("turn_deg_s", std::to_string(degrees(d.turn_rate)));
  EXPECT_FALSE(d.on_branch);
  EXPECT_LE(d.jump, 1.0);
  EXPECT_LE(d.speed_fall, 3000.0);
  EXPECT_LE(d.turn_rate, radians(90.0));
  EXPECT_TRUE(settled);
  EXPECT_GE(lowest, 0.5 * sim.scenario().species.back().stand_height);
}

TEST(BranchLanding, LinedUpBirdFliesStraightIn) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  // On the branch's perpendicular (through (4000, 500, 3000) along (1, 0, 1)), heading in.
  const auto flight =
      make_flight(landing_from(dvec3{4000.0 - 2500.0, 600.0, 3000.0 - 2500.0}, 45.0));
  Simulation& sim = *flight;
  LandingStage stage = LandingStage::none;
  double lowest_x = 1e9;
  run(sim, 10.0, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    if (stage == LandingStage::none) stage = b.landing_stage;
    lowest_x = std::min(lowest_x, b.position.x);
  });
  EXPECT_EQ(stage, LandingStage::curve) << "no detour through the gate";
  EXPECT_GT(lowest_x, 4000.0 - 2600.0) << "it did not turn back";
  EXPECT_EQ(sim.birds()[0].mode, FlightMode::perched);
}

// Birds past the branch and flying away from it must come round (through the gate) to land. The
// flare either perches (at touchdown_speed or slower) or overshoots and goes round again, so that
// a single start is a coin toss: 27 starts around one, each a bird of its own.
TEST(BranchLanding, OvershootingBirdsGoRoundAndPerch) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const Scenario scenario = load_scenario("fig18-branch-path-control");
  std::vector<BirdState> birds;
  for (double dx : {-300.0, 0.0, 300.0})
    for (double dz : {-300.0, 0.0, 300.0})
      for (double heading : {30.0, 45.0, 60.0})
        birds.push_back(CpuSimulation(landing_from(dvec3{6000.0 + dx, 800.0, 5000.0 + dz}, heading))
                            .state()[0]);
  const auto flight = make_flight_with(scenario, birds);
  Simulation& sim = *flight;
  std::vector<bool> went_to_gate(birds.size(), false);
  std::vector<double> perched_at(birds.size(), -1.0);
  run(sim, 120.0, [&](Simulation& s) {
    for (size_t i = 0; i < birds.size(); ++i) {
      const BirdState& b = s.birds()[i];
      went_to_gate[i] = went_to_gate[i] || b.landing_stage == LandingStage::gate;
      if (perched_at[i] < 0.0 && b.mode == FlightMode::perched) perched_at[i] = s.time();
    }
  });
  const size_t perched = static_cast<size_t>(
      std::count_if(perched_at.begin(), perched_at.end(), [](double t) { return t > 0.0; }));
  RecordProperty("perched_of_27_in_120s", std::to_string(perched));
  EXPECT_TRUE(went_to_gate[13])
      << "the middle start, heading straight away, comes round through the gate";
  EXPECT_GE(perched, 20u) << "of 27 in 120 s";
}

// In a wind along the branch's perpendicular a bird cannot grip landing downwind: one that starts
// on the branch's upwind side flies round to the downwind side first and lands into the wind
// within 30 s (measured 17.6 s in 5 m/s, 19.2 s in 8 m/s with one go-round; without that rule the
// 8 m/s bird perched only after 53 s), followed until it perches: never on the ground on the way,
// never pitched past 60 degrees after its first 3 s, never NaN.
TEST(BranchLanding, LandsIntoTheWind) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  for (double wind_speed : {500.0, 800.0}) {
    Scenario scenario = load_scenario("fig18-branch-path-control");
    const Branch& branch = scenario.world.branches[0];
    const dvec3 across = glm::normalize(dvec3{-branch.direction.z, 0.0, branch.direction.x});
    scenario.world.wind = across * wind_speed;
    // 30 m upwind of the branch, heading along it.
    const dvec3 start = branch.point - across * 3000.0 + dvec3{0.0, 300.0, 0.0};
    scenario.flocks[0].spawn_centre = start;
    scenario.flocks[0].heading = std::atan2(branch.direction.z, branch.direction.x);
    const auto flight = make_flight(scenario);
    Simulation& sim = *flight;
    double perched_at = -1.0, worst_pitch = 0.0, lowest = 1e9, slowest_grip = 1e9;
    bool finite = true, touched_down = false;
    int go_rounds = 0;
    FlightMode last_mode = FlightMode::flying;
    dvec3 last_velocity{0.0};
    TouchdownWatch watch;
    run(sim, 60.0, [&](Simulation& s) {
      const BirdState& b = s.birds()[0];
      watch.sample(s.time(), b);
      go_rounds += last_mode == FlightMode::landing && b.mode == FlightMode::flying;
      touched_down = touched_down || b.mode == FlightMode::standing;
      last_mode = b.mode;
      finite = finite && std::isfinite(b.position.x + b.position.y + b.position.z);
      lowest = std::min(lowest, b.position.y - s.world().ground_height);
      if (b.mode == FlightMode::perched) {
        if (perched_at < 0.0) {
          perched_at = s.time();
          slowest_grip = glm::length(last_velocity);
        }
        return;
      }
      last_velocity = b.velocity;
      if (s.time() > 3.0) worst_pitch = std::max(worst_pitch, std::fabs(pitch_angle(b.attitude)));
    });
    const BirdState& b = sim.birds()[0];
    const dvec3 head = b.attitude * dvec3{1.0, 0.0, 0.0};
    const double into_wind = degrees(std::acos(
        std::clamp(-glm::dot(glm::normalize(dvec3{head.x, 0.0, head.z}), across), -1.0, 1.0)));
    RecordProperty("wind_" + std::to_string(int(wind_speed / 100.0)) + "_perched_at_s",
                   std::to_string(perched_at));
    RecordProperty("wind_" + std::to_string(int(wind_speed / 100.0)) + "_head_off_wind_deg",
                   std::to_string(into_wind));
    RecordProperty(
        "wind_" + std::to_string(int(wind_speed / 100.0)) + "_speed_frame_before_grip_cm_s",
        std::to_string(slowest_grip));
    RecordProperty("wind_" + std::to_string(int(wind_speed / 100.0)) + "_go_rounds",
                   std::to_string(go_rounds));
    EXPECT_TRUE(finite);
    EXPECT_GT(perched_at, 0.0) << wind_speed << " cm/s: perched within 60 s";
    EXPECT_LT(into_wind, 45.0) << wind_speed << " cm/s: perched facing into the wind";
    EXPECT_LT(perched_at, 30.0) << wind_speed << " cm/s: round to the downwind side first, then in";
    EXPECT_GE(lowest, 0.0);
    EXPECT_FALSE(touched_down) << wind_speed << " cm/s: never down on the ground on the way";
    EXPECT_LE(slowest_grip, scenario.species[0].touchdown_speed)
        << "a frame (0.03 s) before the grip it is already slow";
    EXPECT_LT(degrees(worst_pitch), 60.0);
    // Issue 40: its feet meet the branch point, slowly over its last wingbeat, and it settles
    // without a jump.
    ASSERT_FALSE(watch.touchdowns().empty()) << wind_speed << " cm/s";
    const Touchdown& d = watch.touchdowns()[0];
    const Species& sp = scenario.species[0];
    RecordProperty("wind_" + std::to_string(int(wind_speed / 100.0)) + "_reach_cm",
                   std::to_string(d.reach));
    RecordProperty("wind_" + std::to_string(int(wind_speed / 100.0)) + "_mean_speed_m_s",
                   std::to_string(d.mean_speed / 100.0));
    EXPECT_TRUE(d.on_branch) << wind_speed << " cm/s";
    EXPECT_LE(d.reach, kGripReach * sp.stand_height) << wind_speed << " cm/s";
    EXPECT_LE(d.mean_speed, sp.touchdown_speed) << wind_speed << " cm/s";
    EXPECT_LE(d.jump, 1.0) << wind_speed << " cm/s";
    EXPECT_LE(d.speed_fall, 3000.0) << wind_speed << " cm/s";
    EXPECT_LE(d.turn_rate, radians(90.0)) << wind_speed << " cm/s";
  }
}

// A bird of Fig. 18 braking for its branch (the branch is its goal).
BirdState braking_for_branch(const World& w) {
  BirdState b;
  b.route = 0;
  b.target = static_cast<uint32_t>(w.routes[0].targets.size());
  b.mode = FlightMode::landing;
  return b;
}

// A bird that flares (hover_final 0, a species' default) grips the branch only within perch_radius
// and at touchdown_speed or slower; faster, it flies on (and goes round).
TEST(BranchLanding, GripsOnlyAtTouchdownSpeed) {
  const Scenario scenario = load_scenario("fig18-branch-path-control");
  const World& w = scenario.world;
  Species sp = eagle();
  sp.hover_final = 0;
  BirdState b = braking_for_branch(w);
  const dvec3 perch = perch_point(sp, w.branches[0]);
  b.position = perch - dvec3{0.5 * sp.perch_radius, 0.0, 0.0};
  b.velocity = dvec3{1.01 * sp.touchdown_speed, 0.0, 0.0};
  BirdState fast = b;
  EXPECT_FALSE(approach_branch(fast, sp, w));
  EXPECT_NE(fast.mode, FlightMode::perched);
  b.velocity = dvec3{0.99 * sp.touchdown_speed, 0.0, 0.0};
  const BirdState before = b;
  EXPECT_TRUE(approach_branch(b, sp, w));
  EXPECT_EQ(b.mode, FlightMode::perched);
  // It holds on where it is, as fast as it flew, and settles onto the perch (issue 40).
  EXPECT_EQ(b.landing_stage, LandingStage::settling);
  EXPECT_EQ(b.position, before.position);
  EXPECT_EQ(b.velocity, before.velocity);
  EXPECT_EQ(b.via_point, perch);
}

// A braking bird sunk under the branch, still sinking faster than it could climb back, goes round
// (it no longer flares down past the branch until its pitch runs away). One sinking slower, or
// not yet that far under, keeps braking.
TEST(BranchLanding, SunkUnderTheBranchGoesRound) {
  const Scenario scenario = load_scenario("fig18-branch-path-control");
  const World& w = scenario.world;
  const Species& sp = scenario.species[0];
  BirdState b = braking_for_branch(w);
  b.landing_stage = LandingStage::curve;
  const dvec3 perch = perch_point(sp, w.branches[0]);
  auto after = [&](double under, double sink) {
    BirdState c = b;
    c.position = perch - dvec3{0.1 * sp.perch_radius, under * sp.perch_radius, 0.0};
    c.velocity = dvec3{0.5 * sp.touchdown_speed, -sink * sp.touchdown_speed, 0.0};
    EXPECT_FALSE(approach_branch(c, sp, w));
    return c;
  };
  const BirdState sunk = after(1.1 * kSunkPerchRadii, 1.1 * kSunkTouchdowns);
  EXPECT_EQ(sunk.mode, FlightMode::flying);
  EXPECT_EQ(sunk.landing_stage, LandingStage::none) << "the landing is planned again";
  EXPECT_EQ(after(0.9 * kSunkPerchRadii, 1.1 * kSunkTouchdowns).mode, FlightMode::landing);
  EXPECT_EQ(after(1.1 * kSunkPerchRadii, 0.9 * kSunkTouchdowns).mode, FlightMode::landing);
}

// --- 7. Moving targets (Fig. 21): a target moving at 5 m/s is caught and the route goes on.
TEST(MovingTarget, IsCaughtAndTheRouteGoesOn) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  const auto flight = make_flight(load_scenario("fig21-moving-target"));
  Simulation& sim = *flight;
  const Target& runner = sim.world().targets[0];
  double entered_at = -1, closest = 1e9;
  run(sim, sim.scenario().duration, [&](Simulation& s) {
    const BirdState& b = s.birds()[0];
    const double d = glm::distance(b.position, target_position(runner, s.time()));
    closest = std::min(closest, d);
    if (entered_at < 0 && d <= runner.radius) entered_at = s.time();
  });
  RecordProperty("entered_at_s", std::to_string(entered_at));
  RecordProperty("closest_cm", std::to_string(closest));
  EXPECT_GT(entered_at, 0.0) << "the moving target's sphere is entered";
  EXPECT_GT(entered_at * glm::length(runner.velocity), 500.0) << "the target had moved by then";
  EXPECT_EQ(sim.birds()[0].targets_reached, 2u) << "the next target of the route is reached too";
}

// --- 8. Nothing in a healthy flight is NaN or infinite: every built-in scenario, in full.
class BuiltinScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinScenario, FliesWithoutNaN) {
  if (!backend_available()) GTEST_SKIP() << backend_name() << " is not available here";
  Scenario scenario = load_scenario(GetParam());
  // The whole flight, of at most 200 birds for a minute's worth (a longer flight, fewer birds, as
  // densely placed: migration-flock's 520 s fly 23); an eighth of that where flocks meet wakes,
  // whose bird-steps cost 8-20 times the others' on the CPU reference (geese-migration's 300 s of
  // 40 birds took 125 s, 5 birds fly them).
  const double budget = any_wake(scenario) ? 200.0 * 60.0 / 8.0 : 200.0 * 60.0;
  const uint32_t most = static_cast<uint32_t>(std::clamp(budget / scenario.duration, 1.0, 200.0));
  const auto flight =
      make_flight(scenario, std::min(most, static_cast<uint32_t>(spawn_birds(scenario).size())));
  Simulation& sim = *flight;
  run(sim, scenario.duration, [](Simulation&) {});
  for (const BirdState& b : sim.birds()) ASSERT_TRUE(finite(b));
}

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const auto& s : builtin_scenarios()) names.push_back(s.name);
  return names;
}

std::string name_of(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param;
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
}

INSTANTIATE_TEST_SUITE_P(Species, Cruise,
                         ::testing::Values("starling", "eagle", "ibis", "goose",
                                           "european_starling"),
                         name_of);
INSTANTIATE_TEST_SUITE_P(
    Species, ClimbDescent,
    ::testing::Values(VerticalCase{"starling", 1000}, VerticalCase{"starling", -1000},
                      VerticalCase{"eagle", 1000}, VerticalCase{"eagle", -1000}),
    [](const auto& info) {
      return info.param.species + (info.param.above > 0 ? "_climb" : "_descent");
    });
INSTANTIATE_TEST_SUITE_P(Fig16, Circling,
                         ::testing::Values("fig16-circling-eagle", "fig16-fixed-rate"), name_of);
INSTANTIATE_TEST_SUITE_P(Figs19And20, ClimbOut,
                         ::testing::Values("fig19-takeoff-no-legs", "fig20-takeoff-legs"), name_of);
INSTANTIATE_TEST_SUITE_P(
    Commands, AirspeedHold,
    ::testing::Values(AirspeedCase{"starling", 600.0}, AirspeedCase{"starling", 1000.0},
                      AirspeedCase{"starling", 1600.0}, AirspeedCase{"eagle", 800.0},
                      AirspeedCase{"eagle", 1000.0}, AirspeedCase{"eagle", 1300.0}),
    [](const ::testing::TestParamInfo<AirspeedCase>& i) {
      return std::string(i.param.species) + "_" + std::to_string(int(i.param.airspeed / 100)) +
             "m_s";
    });
INSTANTIATE_TEST_SUITE_P(All, BuiltinScenario, ::testing::ValuesIn(builtin_names()), name_of);

// Issue 43: a migrant lands on the ground by gliding down to its site (route.h: lands_on_ground):
// the ibis and the goose, in calm air, released as the envelope releases them (7 m up, 30 and 60 m
// from the site straight ahead), at the fast step, judged as the envelope judges (every 6 ms). The
// whole flight, until it is at rest: finite, its body never under the ground, within the envelope's
// limits; it lands (perched) within 60 s, sinking over the 0.24 s before no faster than its legs
// stop within a crouch at the settle's pull (sqrt(2 kSettleDecel crouch_depth): 2.0 and 2.2 m/s;
// its glide path sinks at 1.2 and 1.4 m/s), runs out no farther past perch_radius than its legs
// stop it from its speed before, and stands on the site; its first touch-down, wherever it is,
// keeps issue 40's limits over 30 ms frames (touchdown.h: no jump, its speed falling at 30 m/s^2
// and its body turning at 90 degrees/s at most). Before, braking to touchdown_speed above the site,
// the goose landed 0 of the envelope's 48, sinking onto the ground short of it, again and again.
TEST(GroundLanding, TheMigrantsGlideDownAndLandOnTheirSite) {
  if (!backend_available()) GTEST_SKIP() << "no " << backend_name() << " device";
  for (Species (*preset)() : {ibis, goose})
    for (double distance : {3000.0, 6000.0}) {
      const Species s = preset();
      EnvelopeCase c;
      c.kind = EnvelopeCase::Kind::landing;
      c.rise = -200.0;
      c.distance = distance;
      const EnvelopeFlight flight = envelope_flight(s, {c}, kFastDt);
      const Branch& site = flight.scenario.world.branches.at(0);
      std::unique_ptr<Simulation> sim = make_flight_with(flight.scenario, flight.birds);
      const double frame = flight.scenario.frame_seconds();
      const std::string what = s.name + " " + std::to_string(int(distance / 100.0)) + " m";
      EnvelopeResult judged;
      judged.c = c;
      TouchdownWatch watch(kFrameSeconds);  // issue 40's criteria read 30 ms frames
      double sink = 0.0, landed_at = -1.0;
      std::vector<double> heights;  // a frame's each
      const size_t window = size_t(std::lround(0.24 / frame));
      bool at_rest = false;
      while (sim->time() < 70.0 && !(landed_at > 0.0 && at_rest && watch.settled(sim->time()))) {
        sim->step(flight.scenario.steps_per_frame);
        const BirdState b = sim->birds()[0];
        const double t = sim->time();
        ASSERT_TRUE(is_finite(b)) << what << " at " << t << " s";
        watch.sample(t, b);
        if (landed_at < 0.0 &&
            judge_envelope(judged, b, s, t, flight.scenario.world.ground_height)) {
          ASSERT_EQ(judged.outcome, Outcome::reached)
              << what << ": " << name(judged.outcome) << " at " << t << " s";
        }
        EXPECT_GE(b.position.y - 0.5 * s.box_b, site.point.y) << what << ": its body in the ground";
        heights.push_back(b.position.y);
        if (landed_at < 0.0 && b.mode == FlightMode::perched) {
          landed_at = t;
          if (heights.size() > window)
            sink = (heights[heights.size() - 1 - window] - heights.back()) / (window * frame);
        }
        at_rest = b.mode == FlightMode::perched && b.landing_stage == LandingStage::none;
      }
      const BirdState b = sim->birds()[0];
      RecordProperty(s.name + "_" + std::to_string(int(distance / 100.0)) + "m_landed_s",
                     std::to_string(landed_at));
      ASSERT_GT(landed_at, 0.0) << what << ": it lands";
      EXPECT_LT(landed_at, 60.0) << what << ": within the envelope's 60 s";
      EXPECT_TRUE(at_rest) << what << ": at rest on the site";
      EXPECT_LE(sink, std::sqrt(2.0 * kSettleDecel * s.crouch_depth)) << what << ": its sink, cm/s";
      ASSERT_FALSE(watch.touchdowns().empty()) << what;
      const Touchdown& d = watch.touchdowns().front();
      // The touch-down it landed with (the last) runs out no farther than its legs stop it, at
      // kSettleDecel, from its speed before.
      const Touchdown& landing = watch.touchdowns().back();
      EXPECT_TRUE(landing.on_branch) << what;
      EXPECT_LE(glm::length(horizontal(b.position - site.point)),
                s.perch_radius + landing.mean_speed * landing.mean_speed / (2.0 * kSettleDecel))
          << what << ": its run-out";
      EXPECT_EQ(b.mode, FlightMode::perched) << what;
      EXPECT_NEAR(b.position.y, site.point.y + s.stand_height, 1.0) << what << ": its feet on it";
      EXPECT_LE(d.jump, 1.0) << what;
      EXPECT_LE(d.speed_fall, 3000.0) << what;
      EXPECT_LE(d.turn_rate, radians(90.0)) << what;
    }
}

}  // namespace
}  // namespace aeroflock
