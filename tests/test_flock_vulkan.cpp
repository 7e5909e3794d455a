// Flocking on the compute shaders against the CPU reference (docs/MODEL.md "What a flock must
// show", criterion 6), Khronos validation layer on: the neighbour grid (grid_*.comp, perceive.comp)
// finds the same neighbours, the social goal agrees within float rounding, and the flock metrics
// agree over 20 s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <glm/geometric.hpp>

#include "flock_run.h"
#include "formation_run.h"
#include "gpu/gpu_simulation.h"
#include "gpu_test_device.h"
#include "io/scenario_file.h"
#include "model/body.h"
#include "model/flock.h"
#include "model/flock_geometry.h"
#include "model/simulation.h"

namespace aeroflock {
namespace {

using glm::dvec3;
using testing::flocking_bird;

// The default scenario with `birds` placed by the test (the targets and species as the file has
// them).
Scenario flocking_scenario() {
  Scenario s = load_scenario("default");
  for (Flock& f : s.flocks) f.flocking = true;
  return s;
}

struct Compared {
  size_t birds = 0, same_neighbours = 0, seeing = 0;
  double worst_direction = 0.0, worst_airspeed = 0.0, worst_nearest = 0.0;
  uint64_t searched_again = 0;  // of the device's sampled searches (GpuSimulation::searches)
};

// Perceives once on each backend from the same state (a frame of no steps) and compares.
Compared perceive_on_both(gpu::Device& device, const Scenario& scenario,
                          const std::vector<BirdState>& birds) {
  CpuSimulation cpu(scenario, birds);
  gpu::GpuSimulation gpu(device, scenario, birds);
  cpu.step(0);
  gpu.step(0);
  const std::vector<Perception>& a = *cpu.snapshot().perception;
  const std::vector<Perception>& b = *gpu.snapshot().perception;
  Compared c;
  c.birds = birds.size();
  c.searched_again = gpu.searches().again;
  for (size_t i = 0; i < birds.size(); ++i) {
    const bool same = a[i].neighbours == b[i].neighbours && a[i].seen_key == b[i].seen_key;
    c.same_neighbours += same;
    c.seeing += a[i].neighbours > 0;
    if (!same) continue;
    c.worst_direction = std::max(c.worst_direction, glm::length(a[i].direction - b[i].direction));
    c.worst_airspeed = std::max(c.worst_airspeed, std::fabs(a[i].airspeed - b[i].airspeed));
    c.worst_nearest = std::max(c.worst_nearest, std::fabs(a[i].nearest - b[i].nearest));
  }
  return c;
}

// Nearly every bird sees the same neighbours on both backends and steers for the same goal.
void expect_same_perception(const Compared& c) {
  EXPECT_GT(c.seeing, c.birds * 9 / 10);
  EXPECT_GE(double(c.same_neighbours), 0.999 * double(c.birds))
      << c.same_neighbours << " of " << c.birds;
  EXPECT_LT(c.worst_direction, 1e-4);  // a unit vector
  EXPECT_LT(c.worst_airspeed, 0.05);   // cm/s of ~1000
  EXPECT_LT(c.worst_nearest, 0.01);    // cm of ~100
  std::printf(
      "same neighbours for %zu of %zu birds (%zu seeing); worst direction %.2g, airspeed %.2g "
      "cm/s, nearest "
      "%.2g cm\n",
      c.same_neighbours, c.birds, c.seeing, c.worst_direction, c.worst_airspeed, c.worst_nearest);
}

TEST(GpuFlock, SameNeighboursAndSocialGoalFromOneState) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = flocking_scenario();
  // The default flock after 5 s of flight, flocking: spacing as the criteria have it.
  CpuSimulation flown(scenario);
  while (flown.time() < 5.0) flown.step_frame();
  expect_same_perception(perceive_on_both(device, scenario, flown.birds()));
  // Issue 41: the same with the separation heeding all round if the preset's does not, or not if
  // it does (separation_all_round): the k nearest sought all round, the blind sector then hiding
  // them from all but the separation.
  Scenario flipped = scenario;
  for (Species& s : flipped.species) s.separation_all_round = s.separation_all_round != 0.0 ? 0 : 1;
  expect_same_perception(perceive_on_both(device, flipped, flown.birds()));
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 41: the murmuration's real starlings separate from where their neighbours will be nearest
// (separation_lookahead): 1,000 of them after 5 s, their social goals the same on both backends.
TEST(GpuFlock, SameSocialGoalWhereTheNeighboursWillBeNearest) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("murmuration");
  ASSERT_GT(scenario.species[scenario.flocks[0].species].separation_lookahead, 0.0);
  CpuSimulation flown(scenario, 1000);
  while (flown.time() < 5.0) flown.step_frame();
  expect_same_perception(perceive_on_both(device, scenario, flown.birds()));
  EXPECT_EQ(device.validation_errors(), 0u);
  // And the lookahead acts in this state: judged where their neighbours are, some steer otherwise.
  Scenario now = scenario;
  now.species[now.flocks[0].species].separation_lookahead = 0.0;
  CpuSimulation ahead(scenario, flown.birds()), here(now, flown.birds());
  ahead.step(0);
  here.step(0);
  const std::vector<Perception>& a = *ahead.snapshot().perception;
  const std::vector<Perception>& h = *here.snapshot().perception;
  size_t otherwise = 0;
  for (size_t i = 0; i < a.size(); ++i)
    otherwise += glm::distance(a[i].direction, h[i].direction) > 1e-3;
  EXPECT_GT(otherwise, a.size() / 20) << otherwise << " of " << a.size() << " steer otherwise";
  std::printf("%zu of %zu birds steer otherwise without the lookahead\n", otherwise, a.size());
}

// The scenario's birds flown `seconds` on the CPU reference, then on each backend from that state,
// each having perceived and recorded the forces of its next step (a frame of no steps).
struct BothBackends {
  std::vector<BirdState> birds;
  std::unique_ptr<CpuSimulation> cpu;
  std::unique_ptr<gpu::GpuSimulation> gpu;
};
BothBackends from_one_state(gpu::Device& device, const Scenario& scenario, double seconds) {
  CpuSimulation flown(scenario);
  while (flown.time() < seconds) flown.step_frame();
  BothBackends both{flown.birds(), nullptr, nullptr};
  both.cpu = std::make_unique<CpuSimulation>(scenario, both.birds);
  both.gpu = std::make_unique<gpu::GpuSimulation>(device, scenario, both.birds);
  both.cpu->step(0, true);
  both.gpu->step(0, true);
  return both;
}

// Issue 43: with the wakes on, each bird meets the same wakes on both backends (the same birds
// ahead, their lift, wingbeat and air velocity), the forces of its next step agree within float
// rounding, and a frame later so do the flock's states (the wakes moved on within the frame).
TEST(GpuFlock, TheWakesMetAreTheReferences) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  Scenario scenario = flocking_scenario();
  for (Flock& f : scenario.flocks) f.wake = true;
  BothBackends both = from_one_state(device, scenario, 5.0);
  const std::vector<BirdState>& birds = both.birds;
  CpuSimulation& cpu = *both.cpu;
  gpu::GpuSimulation& gpu = *both.gpu;
  const std::vector<Perception>& a = *cpu.snapshot().perception;
  const std::vector<Perception>& b = *gpu.snapshot().perception;
  const std::vector<StepForces>& fa = *cpu.snapshot().forces;
  const std::vector<StepForces>& fb = *gpu.snapshot().forces;
  size_t compared = 0, with_wakes = 0;
  double worst_force = 0.0, worst_lift = 0.0;
  for (size_t i = 0; i < birds.size(); ++i) {
    if (a[i].neighbours != b[i].neighbours || a[i].seen_key != b[i].seen_key) continue;
    ++compared;
    ASSERT_EQ(a[i].wakes, b[i].wakes) << "bird " << i;
    with_wakes += a[i].wakes > 0;
    for (uint32_t k = 0; k < a[i].wakes; ++k) {
      const WakeSource &x = a[i].wake[k], &y = b[i].wake[k];
      worst_lift = std::max(worst_lift, std::fabs(x.lift - y.lift) / x.lift);
      EXPECT_NEAR(x.amplitude, y.amplitude, 1e-6);
      EXPECT_NEAR(x.frequency, y.frequency, 1e-5);
      EXPECT_NEAR(std::remainder(x.phase - y.phase, 2.0 * kPi), 0.0, 1e-5);
      EXPECT_LT(glm::length(x.air_velocity - y.air_velocity), 1e-2);
    }
    const double weight = scenario.species[birds[i].species].mass * kGravity;
    worst_force = std::max(
        worst_force, glm::length(fa[i].total - fb[i].total) / (glm::length(fa[i].total) + weight));
  }
  RecordProperty("birds_meeting_wakes", std::to_string(with_wakes));
  RecordProperty("worst_force_relative", std::to_string(worst_force));
  EXPECT_GE(double(compared), 0.999 * double(birds.size()));
  EXPECT_GT(with_wakes, birds.size() / 2);
  EXPECT_LT(worst_lift, 1e-6);
  EXPECT_LT(worst_force, 1e-5);
  // A frame later (the wakes advanced within it, step by step).
  cpu.step(scenario.steps_per_frame);
  gpu.step(scenario.steps_per_frame);
  double worst_position = 0.0;
  for (size_t i = 0; i < birds.size(); ++i)
    worst_position =
        std::max(worst_position, glm::length(cpu.birds()[i].position - gpu.birds()[i].position));
  RecordProperty("worst_position_cm_after_a_frame", std::to_string(worst_position));
  EXPECT_LT(worst_position, 0.05);
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 43: a loose group in formation holds its route's height on the shaders as on the CPU
// (formation_run.h; test_formation's Formation.ALooseGroupInFormationHoldsItsRoutesHeight).
TEST(GpuFlock, ALooseGroupInFormationHoldsItsRoutesHeight) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  for (uint64_t seed : {1u, 2u, 3u})
    testing::expect_route_height_held(
        seed, [&](const Scenario& s) { return std::make_unique<gpu::GpuSimulation>(device, s); });
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 43's V from a loose start and its energy on the device (formation_run.h), seeds 1-2 and
// one with the wakes off (the CPU reference flies four and two: test_formation). The followers
// directly behind are printed, not judged: two seeds hold too few of them. Whether one settles
// there a span or more back, and locks to the anti-phase, or drifts through at less than a span
// without, is chance: on the device seed 1 has 42 follower-snapshots there, 21 in anti-phase
// (one follower drifting back from 0.2 to 1 span over 19 s, 94 degrees from the spatial phase on
// average, then 14 s at 1.1 spans in anti-phase), seed 2 8 and none; seeds 1-8 and 10 70 of 100
// (`aeroflock run` of ibis-v with those seeds). The CPU reference's seeds 1-16: 166 of 167.
TEST(GpuFlock, ALooseGroupOfIbisesFormsAVAndItsFollowersSpendLess) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  testing::expect_ibis_v_forms_a_v_and_saves(
      [&](const Scenario& s, std::vector<BirdState> birds) {
        return std::make_unique<gpu::GpuSimulation>(device, s, std::move(birds));
      },
      2, 1, false);
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 43's energy criterion on the device (formation_run.h).
TEST(GpuFlock, AFollowerSpendsLessPowerThanAlone) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  testing::expect_a_follower_saves_power([&](const Scenario& s, std::vector<BirdState> birds) {
    return std::make_unique<gpu::GpuSimulation>(device, s, std::move(birds));
  });
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 43: formation flying on both backends. A loose group of seven formation eagles, and
// ibis-v's 14 ibises (their wingbeat led by their airspeed's rate, speed_lead), after 40 s
// (followers in and around V places): each bird's formation (its heading, airspeed and wingbeat's
// phase rate, from the upwash it predicts at probes around it) agrees within float rounding, and a
// second later so do the birds' places.
class GpuFormation : public ::testing::TestWithParam<bool> {};

TEST_P(GpuFormation, FormationFlyingIsTheReferences) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario =
      GetParam() ? load_scenario("ibis-v") : testing::formation_scenario(7, true);
  BothBackends both = from_one_state(device, scenario, 40.0);
  const std::vector<BirdState>& birds = both.birds;
  CpuSimulation& cpu = *both.cpu;
  gpu::GpuSimulation& gpu = *both.gpu;
  const std::vector<Perception>& a = *cpu.snapshot().perception;
  const std::vector<Perception>& b = *gpu.snapshot().perception;
  size_t in_formation = 0;
  double worst_direction = 0.0, worst_airspeed = 0.0, worst_phase_rate = 0.0;
  for (size_t i = 0; i < birds.size(); ++i) {
    ASSERT_EQ(a[i].seen_key, b[i].seen_key) << "bird " << i;
    ASSERT_EQ(a[i].wakes, b[i].wakes) << "bird " << i;
    in_formation += a[i].phase_rate != 0.0;
    worst_direction = std::max(worst_direction, glm::length(a[i].direction - b[i].direction));
    worst_airspeed = std::max(worst_airspeed, std::fabs(a[i].airspeed - b[i].airspeed));
    worst_phase_rate = std::max(worst_phase_rate, std::fabs(a[i].phase_rate - b[i].phase_rate));
  }
  std::printf(
      "%zu of %zu birds in formation; worst direction %.2g, airspeed %.2g cm/s, phase rate "
      "%.2g rad/s\n",
      in_formation, birds.size(), worst_direction, worst_airspeed, worst_phase_rate);
  RecordProperty("birds_in_formation", std::to_string(in_formation));
  EXPECT_GE(in_formation, 2u);
  EXPECT_LT(worst_direction, 1e-3);
  EXPECT_LT(worst_airspeed, 0.5);     // cm/s of ~1000
  EXPECT_LT(worst_phase_rate, 1e-3);  // rad/s of up to kPhaseReach / formation_time
  const uint32_t second = static_cast<uint32_t>(std::lround(1.0 / scenario.frame_seconds()));
  for (uint32_t k = 0; k < second; ++k) {
    cpu.step_frame();
    gpu.step_frame();
  }
  double worst_position = 0.0;
  for (size_t i = 0; i < birds.size(); ++i)
    worst_position =
        std::max(worst_position, glm::length(cpu.birds()[i].position - gpu.birds()[i].position));
  RecordProperty("worst_position_cm_after_a_second", std::to_string(worst_position));
  EXPECT_LT(worst_position, 1.0);
  EXPECT_EQ(device.validation_errors(), 0u);
}

INSTANTIATE_TEST_SUITE_P(GpuFlock, GpuFormation, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& p) {
                           return std::string(p.param ? "ibis_v" : "formation_eagles");
                         });

// The same 1,000 km east and 300 km north: the grid's cells and the birds' places in them are
// exact on the device (world tiles), so it finds what it finds at the origin.
TEST(GpuFlock, SameNeighboursAndSocialGoalAThousandKilometresOut) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const dvec3 offset(1.0e8, 0.0, -3.0e7);
  const Scenario scenario = flocking_scenario();
  CpuSimulation flown(scenario);
  while (flown.time() < 5.0) flown.step_frame();
  std::vector<BirdState> birds = flown.birds();
  for (BirdState& b : birds) b.position += offset;
  const Compared c = perceive_on_both(device, moved_by(scenario, offset), birds);
  EXPECT_GT(c.seeing, c.birds * 9 / 10);
  EXPECT_GE(double(c.same_neighbours), 0.999 * double(c.birds))
      << c.same_neighbours << " of " << c.birds;
  EXPECT_LT(c.worst_direction, 1e-4);
  EXPECT_LT(c.worst_airspeed, 0.05);
  EXPECT_LT(c.worst_nearest, 0.01);
  std::printf(
      "1,000 km out: same neighbours for %zu of %zu birds (%zu seeing); worst direction %.2g, "
      "airspeed %.2g "
      "cm/s, nearest %.2g cm\n",
      c.same_neighbours, c.birds, c.seeing, c.worst_direction, c.worst_airspeed, c.worst_nearest);
  EXPECT_EQ(device.validation_errors(), 0u);
}

TEST(GpuFlock, GridFindsTheSameOnAdversarialInputs) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = flocking_scenario();
  const double cell =
      grid_shape(scenario.species, {flocking_bird(dvec3{0.0}, dvec3{1000.0, 0.0, 0.0})}).cell;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // All in one cell (with exact ties), on cell borders, cells whose slots collide, two flocks in
  // one place, a sparse flock, one bird, none.
  std::vector<BirdState> one_cell;
  for (int i = 0; i < 300; ++i)
    one_cell.push_back(flocking_bird(
        dvec3{0.25 * cell * unit(rng), 4000.0 + 10.0 * (i % 3), 0.25 * cell * unit(rng)},
        dvec3{1000.0, 0.0, 0.0}));
  // On cell borders: one coordinate on a border, the others anywhere (a lattice would make exact
  // ties of distance, which float and double break differently).
  std::vector<BirdState> borders;
  for (int x = -3; x <= 3; ++x)
    for (int n = 0; n < 40; ++n)
      borders.push_back(
          flocking_bird(dvec3{cell * x, 4000.0 + 600.0 * unit(rng), 600.0 * unit(rng)},
                        dvec3{0.0, 0.0, -1000.0}));
  // The table of cells (grid.glsl: grid_slot) has room for 4,096 slots for 160 birds, and its
  // sides are fitted to the flock (gpu/grid_table.h): a line of birds through 208 cells is longer
  // than a side can be (64 cells along x, with 8 along y and along z), so cells 64 apart start
  // their search at one slot and most cells' slots are taken by another's (the search goes on
  // past them, grid_count.comp and flock.glsl).
  std::vector<BirdState> line;
  for (int n = 0; n < 160; ++n)
    line.push_back(flocking_bird(
        dvec3{1.3 * cell * n + 7.0 * unit(rng), 4000.0 + 50.0 * unit(rng), 50.0 * unit(rng)},
        dvec3{0.0, 0.0, 1000.0}));  // across the line: no bird has all behind it
  // Two flocks in the same cells: each bird sees its own flock alone.
  std::vector<BirdState> two_flocks;
  for (int n = 0; n < 200; ++n)
    two_flocks.push_back(flocking_bird(
        dvec3{3.0 * cell * unit(rng), 4000.0 + 2.0 * cell * unit(rng), 3.0 * cell * unit(rng)},
        dvec3{0.0, 0.0, 1000.0}, n % 2));
  for (const auto& [what, birds] :
       {std::pair{"one cell", one_cell}, std::pair{"borders", borders},
        std::pair{"cells sharing slots", line}, std::pair{"two flocks", two_flocks}}) {
    const Compared c = perceive_on_both(device, scenario, birds);
    EXPECT_EQ(c.seeing, c.birds) << what;
    // Exact ties and borders may fall either way in float: all but 0.1 % agree.
    EXPECT_GE(double(c.same_neighbours), 0.999 * double(c.birds))
        << what << ": " << c.same_neighbours;
    if (what == std::string("cells sharing slots")) {
      EXPECT_GT(c.searched_again, 0u);
    }
  }
  // Two species that see different numbers of neighbours, and see as far (the search's k is then
  // the bird's own, and its order reaches the farther).
  Scenario unlike = scenario;
  unlike.species[1].neighbours = 3;
  unlike.species[1].perception_radius = 0.5 * unlike.species[0].perception_radius;
  unlike.species[1].separation_all_round = unlike.species[0].separation_all_round != 0.0 ? 0 : 1;
  std::vector<BirdState> two_species = two_flocks;
  for (size_t n = 0; n < two_species.size(); ++n) two_species[n].species = uint32_t(n % 2);
  const Compared mixed = perceive_on_both(device, unlike, two_species);
  EXPECT_EQ(mixed.seeing, mixed.birds);
  EXPECT_GE(double(mixed.same_neighbours), 0.999 * double(mixed.birds))
      << "two species: " << mixed.same_neighbours;
  // Sparse: 300 birds over 300 m, most alone in their cells and many out of sight of any other.
  std::vector<BirdState> sparse;
  for (int n = 0; n < 300; ++n)
    sparse.push_back(
        flocking_bird(dvec3{30000.0 * unit(rng), 4000.0 + 3000.0 * unit(rng), 30000.0 * unit(rng)},
                      dvec3{1000.0, 0.0, 0.0}));
  const Compared apart = perceive_on_both(device, scenario, sparse);
  EXPECT_GT(apart.seeing, 0u);
  EXPECT_LT(apart.seeing, apart.birds);
  EXPECT_EQ(apart.same_neighbours, apart.birds);
  const Compared one = perceive_on_both(
      device, scenario, {flocking_bird(dvec3{0.0, 4000.0, 0.0}, dvec3{1000.0, 0.0, 0.0})});
  EXPECT_EQ(one.same_neighbours, 1u);
  EXPECT_EQ(one.seeing, 0u);
  gpu::GpuSimulation none(device, scenario, std::vector<BirdState>{});
  none.step(100);
  EXPECT_TRUE(none.snapshot().perception->empty());
  EXPECT_EQ(device.validation_errors(), 0u);
}

// docs/MODEL.md's criteria 1-4 on the compute shaders: the default starlings, 20 to 80 s.
// Issue 13: frames recorded several to a submission (step_frames) fly exactly as the same frames
// submitted one by one: a flocking flock (the perception each frame) and a bird chasing a moving
// target (each frame's targets), bit for bit; a submission's last frame is the one read back.
TEST(GpuFrames, SeveralFramesASubmissionFlyAsFramesOneByOne) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  for (const char* name : {"default", "fig21-moving-target"}) {
    SCOPED_TRACE(name);
    const Scenario s = load_scenario(name);
    gpu::GpuSimulation batched(device, s, 300), single(device, s, 300);
    batched.step_frames(7);
    EXPECT_EQ(batched.frames(), 7u);
    batched.step_frames(20);  // a submission of 16, then one of 4
    EXPECT_EQ(batched.ready_frame(), 23u);
    for (int f = 0; f < 27; ++f) single.step_frame();
    ASSERT_EQ(batched.frames(), single.frames());
    ASSERT_EQ(batched.time(), single.time());
    const std::vector<BirdState> a = batched.birds(), b = single.birds();
    ASSERT_EQ(a.size(), b.size());
    size_t same = 0;
    for (size_t i = 0; i < a.size(); ++i)
      same += a[i].position == b[i].position && a[i].velocity == b[i].velocity &&
              a[i].attitude == b[i].attitude && a[i].omega == b[i].omega &&
              a[i].phase == b[i].phase && a[i].amplitude == b[i].amplitude &&
              a[i].targets_reached == b[i].targets_reached && a[i].mode == b[i].mode;
    EXPECT_EQ(same, a.size());
  }
}

// Issue 44: each frame's passes timed on the device (timestamps; aeroflock bench reports them):
// every frame of every submission, in order, the grid's passes, the perception and the steps each
// taking time; none for the grid or the perception of a flock that does not flock; the flight the
// same bit for bit as untimed.
TEST(GpuFrames, EachFramesPassesAreTimedOnTheDevice) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  if (!gpu::Timestamps::supported(device)) GTEST_SKIP() << "the device writes no timestamps";
  for (const bool flocking : {true, false}) {
    SCOPED_TRACE(flocking ? "flocking" : "not flocking");
    Scenario s = load_scenario("default");
    for (Flock& f : s.flocks) f.flocking = flocking;
    gpu::GpuSimulation timed(device, s, 300), untimed(device, s, 300);
    ASSERT_TRUE(timed.time_passes());
    timed.step_frames(20);  // a submission of 16, then one of 4
    untimed.step_frames(20);
    const std::vector<BirdState> a = timed.birds(), b = untimed.birds();
    size_t same = 0;
    for (size_t i = 0; i < a.size(); ++i)
      same += a[i].position == b[i].position && a[i].velocity == b[i].velocity;
    EXPECT_EQ(same, a.size());
    const std::vector<gpu::GpuSimulation::PassTimes>& t = timed.pass_times();
    ASSERT_EQ(t.size(), 20u);
    for (size_t f = 0; f < t.size(); ++f) {
      EXPECT_EQ(t[f].frame, f + 1);
      EXPECT_GT(t[f].steps_ms, 0.0);
      if (flocking) {
        EXPECT_GT(t[f].grid_ms, 0.0);
        EXPECT_GT(t[f].perception_ms, 0.0);
      } else {
        EXPECT_EQ(t[f].grid_ms, 0.0);
        EXPECT_EQ(t[f].perception_ms, 0.0);
      }
    }
    EXPECT_EQ(untimed.pass_times().size(), 0u);
  }
}

// Issue 44: a cell of the neighbour grid holding more birds than a shader's loops may look
// through (lavapipe ends them after 65,535 turns) makes reading the frame an error naming the
// search, not a perception silently cut short. 70,000 birds in a metre cube.
TEST(GpuFlock, ASearchCutShortByTheDriverIsAnError) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  if (device.driver().find("llvmpipe") == std::string::npos)
    GTEST_SKIP() << "only lavapipe's limit on loops is known";
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 100.0);
  std::vector<BirdState> birds;
  for (int i = 0; i < 70000; ++i)
    birds.push_back(flocking_bird(dvec3{u(rng), 2000.0 + u(rng), u(rng)}, dvec3{1000.0, 0.0, 0.0}));
  gpu::GpuSimulation sim(device, flocking_scenario(), birds);
  sim.step(0);
  try {
    sim.snapshot();
    FAIL() << "a search cut short was read as a perception";
  } catch (const gpu::Error& e) {
    EXPECT_NE(std::string(e.what()).find("ended the neighbour search of"), std::string::npos)
        << e.what();
  }
}

// Issue 43: the migrants' grid. At cells of 128 cm (under a twelfth of their 20 m perception) a
// goose alone searched 16 rings and outran lavapipe's loop budget: geese-migration's 96 geese
// stopped at 1 s on Vulkan. Its first 3 s, every bird, now fly with every search whole.
TEST(GpuFlock, TheGeeseSkeinsSearchWhole) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("geese-migration");
  gpu::GpuSimulation sim(device, scenario);
  ASSERT_EQ(sim.bird_count(), 96u);
  while (sim.time() < 3.0) {
    sim.step_frame();
    ASSERT_NO_THROW(sim.snapshot()) << "at " << sim.time() << " s";
  }
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 44: the grid's cell follows how far the searches reach (grid_cell_for). Of
// geese-migration's 96 geese 80 see fewer than 7 within 20 m and search all their sight: some 2,600
// cells of 2.56 m, or 27 of 20 m (1,000 such geese: perception 29 ms a frame on lavapipe with the
// first, 3.4 with the second). Whatever the cell, each bird sees what the CPU reference sees from
// the same state, every frame; the default's dense starlings keep grid_shape's cell.
TEST(GpuFlock, TheGridsCellFollowsTheSearchesAndChangesNoNeighbour) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("geese-migration");
  gpu::GpuSimulation sim(device, scenario);
  const double first = sim.grid_cell();
  size_t compared = 0, same = 0, frames_compared = 0;
  while (sim.time() < 2.0) {
    const std::vector<BirdState> before = sim.birds();
    const uint64_t frame = sim.frames(), step = sim.steps();
    sim.step_frame();
    const Snapshot s = sim.snapshot();
    std::vector<Perception> cpu;
    perceive(before, scenario.species, scenario.world, frame, step, scenario.frame_seconds(),
             grid_shape(scenario.species, before), cpu);
    ++frames_compared;
    for (size_t i = 0; i < before.size(); ++i) {
      if (cpu[i].neighbours == 0) continue;
      ++compared;
      same += cpu[i].neighbours == (*s.perception)[i].neighbours &&
              cpu[i].seen_key == (*s.perception)[i].seen_key;
    }
  }
  EXPECT_EQ(first, 256.0);
  EXPECT_EQ(sim.grid_cell(), 2048.0);
  EXPECT_GT(compared, 60 * 90u);
  EXPECT_GE(double(same), 0.999 * double(compared)) << same << " of " << compared;
  std::printf(
      "geese: cells of %g cm, then %g; the same neighbours for %zu of %zu birds' looks "
      "over %zu frames\n",
      first, sim.grid_cell(), same, compared, frames_compared);
  gpu::GpuSimulation starlings(device, load_scenario("default"));
  while (starlings.time() < 1.0) starlings.step_frame();
  starlings.snapshot();
  EXPECT_EQ(starlings.grid_cell(), 256.0);
  EXPECT_EQ(device.validation_errors(), 0u);
}

TEST(GpuFlock, TheDefaultStarlingsKeepSpacingOrderAndCohesionAndFlyTheRoute) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("default");
  gpu::GpuSimulation sim(device, scenario);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 20.0, 80.0);
  testing::expect_flock_criteria(run, scenario, 0);
  testing::expect_structure_criteria(run);  // the field's (docs/FIELD.md)
  // The grid's table holds the flock (gpu/grid_table.h): its searches find every cell at the first
  // look. With sides that suit no shape they wrapped its height every 4 cells, and from 10 s on
  // nearly every bird searched twice.
  const gpu::GpuSimulation::Searches searches = sim.searches();
  EXPECT_GT(searches.sampled, 100'000u);
  EXPECT_LT(double(searches.again), 0.01 * double(searches.sampled))
      << searches.again << " of " << searches.sampled;
  std::printf("searched again: %llu of %llu sampled searches\n",
              static_cast<unsigned long long>(searches.again),
              static_cast<unsigned long long>(searches.sampled));
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 41: the murmuration's real starlings, as FlockCriteria.TheMurmurationsEuropeanStarlings...
// on the CPU reference.
TEST(GpuFlock, TheMurmurationsEuropeanStarlingsKeepTheFieldsSpacingInMetres) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("murmuration");
  gpu::GpuSimulation sim(device, scenario, 1000);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 30.0, 60.0);
  testing::expect_flock_criteria(run, scenario, 0, {.straight_legs = false});
  testing::expect_murmuration_structure(run);
  EXPECT_EQ(device.validation_errors(), 0u);
}

// Issue 39: a migrating flock stays short along its flight and whole. Before the cohesion pulled
// along the flight (cohesion_pull), these 300 starlings of `migration` stretched into a column, 63
// m long at 120 s and 172 m at 600 s, and broke at 660 s; with it, 10-19 m long, one cluster to the
// leg's end (docs/MODEL.md "Why p: a flock over hours").
TEST(GpuFlock, AMigratingFlockStaysShortAlongItsFlightAndWhole) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("migration");
  gpu::GpuSimulation sim(device, scenario, 300);
  double longest = 0.0, smallest_cluster = 1.0;
  for (int minute = 1; minute <= 10; ++minute) {
    while (sim.time() < 60.0 * minute - 1e-9) sim.step_frames(100);
    const std::vector<BirdState>& birds = sim.birds();
    const FlockExtent e = flock_extent(birds);
    ASSERT_EQ(e.finite, birds.size()) << "no NaN, no quarantine";
    const glm::dvec3 along = glm::normalize(e.mean_velocity);
    double front = -1e30, back = 1e30;
    for (const BirdState& b : birds) {
      const double x = glm::dot(b.position - e.centre, along);
      front = std::max(front, x), back = std::min(back, x);
    }
    longest = std::max(longest, front - back);
    smallest_cluster =
        std::min(smallest_cluster, flock_metrics(birds, sim.scenario().species).largest_cluster);
  }
  RecordProperty("longest_along_flight_cm", std::to_string(longest));
  RecordProperty("smallest_largest_cluster", std::to_string(smallest_cluster));
  std::printf("longest along its flight %.1f m, smallest largest cluster %.3f\n", longest / 100.0,
              smallest_cluster);
  EXPECT_LE(longest, 4000.0) << "40 m";
  EXPECT_GE(smallest_cluster, 0.95);
  EXPECT_EQ(device.validation_errors(), 0u);
}

// The flock metrics of the default starlings over 20 s agree within 5 % between the backends.
TEST(GpuFlock, FlockMetricsOverTwentySecondsAgreeWithTheReference) {
  AEROFLOCK_DEVICE_OR_SKIP(device, false);
  const Scenario scenario = load_scenario("default");
  CpuSimulation cpu(scenario);
  gpu::GpuSimulation gpu(device, scenario);
  const testing::FlockRun a = testing::fly_flock(cpu, 0, 0.0, 20.0);
  const testing::FlockRun b = testing::fly_flock(gpu, 0, 0.0, 20.0);
  EXPECT_NEAR(b.mean_median_nearest, a.mean_median_nearest, 0.05 * a.mean_median_nearest);
  EXPECT_NEAR(b.mean_polarisation, a.mean_polarisation, 0.05 * a.mean_polarisation);
  EXPECT_NEAR(b.mean_largest_cluster, a.mean_largest_cluster, 0.05 * a.mean_largest_cluster);
  // A fraction of a percent (a pair of birds is 0.2 %): within a quarter of a percentage point.
  EXPECT_NEAR(b.mean_too_close, a.mean_too_close, 0.0025);
  std::printf(
      "CPU, Vulkan over 20 s: median nearest %.1f, %.1f cm; polarisation %.4f, %.4f; largest "
      "cluster "
      "%.4f, %.4f; too close %.4f, %.4f\n",
      a.mean_median_nearest, b.mean_median_nearest, a.mean_polarisation, b.mean_polarisation,
      a.mean_largest_cluster, b.mean_largest_cluster, a.mean_too_close, b.mean_too_close);
  EXPECT_EQ(b.non_finite, 0u);
  EXPECT_EQ(device.validation_errors(), 0u);
}

}  // namespace
}  // namespace aeroflock
