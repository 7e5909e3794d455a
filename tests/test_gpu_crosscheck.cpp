// The compute shaders against the CPU reference: one step's forces, torques and state change for
// many random but valid birds, and the first seconds of every built-in scenario. Both start from
// the same float-rounded states, so they differ only by float-vs-double rounding. Runs with the
// Khronos validation layer on; any validation error fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "gpu/device.h"
#include "gpu/gpu_simulation.h"
#include "io/scenario_file.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/route.h"
#include "model/simulation.h"
#include "model/step.h"

namespace aeroflock {
namespace {

using glm::dvec3;

std::unique_ptr<gpu::Device> open_device() {
  try {
    if (gpu::Device::list_devices().empty()) return nullptr;
    return std::make_unique<gpu::Device>(gpu::headless(-1, true));
  } catch (const gpu::Error&) {
    return nullptr;
  }
}

#define DEVICE_OR_SKIP(device)                                   \
  const auto device = open_device();                             \
  if (!device) GTEST_SKIP() << "no Vulkan device on this machine"

// The state as the GPU holds it: every value rounded to float.
BirdState rounded(const BirdState& b) { return gpu::unpack(gpu::pack(b)); }

// A world with a target route and a landing route, for both species.
Scenario probe_scenario() {
  return parse_scenario(R"(
[[targets]]
name = "a"
centre = [5000.0, 3000.0, 2000.0]
radius = 300.0
velocity = [100.0, 0.0, -50.0]
[[targets]]
name = "b"
centre = [-4000.0, 2500.0, 1000.0]
[[branches]]
name = "oak"
point = [1000.0, 500.0, 1000.0]
direction = [1.0, 0.0, 1.0]
[[routes]]
name = "tour"
targets = ["a", "b"]
loop = true
[[routes]]
name = "perch"
targets = []
branch = "oak"
[[flocks]]
species = "starling"
route = "tour"
)", "probe.toml");
}

// Random but valid birds: flying at all attitudes a bird takes, near the ground, taking off,
// and on the final approach to the branch.
std::vector<BirdState> random_birds(const Scenario& s, size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
  std::vector<BirdState> birds;
  for (size_t i = 0; i < count; ++i) {
    BirdState b;
    b.species = static_cast<uint32_t>(i % s.species.size());
    const Species& sp = s.species[b.species];
    b.route = 0;
    b.target = static_cast<uint32_t>(i / 2 % 2);
    b.position = dvec3{in(-6000, 6000), in(500, 5000), in(-6000, 6000)};
    const double heading = in(-kPi, kPi);
    b.attitude = glm::angleAxis(heading, dvec3{0, -1, 0}) * glm::angleAxis(in(-0.5, 0.5), dvec3{0, 0, 1}) *
                 glm::angleAxis(in(-0.7, 0.7), dvec3{1, 0, 0});
    b.velocity = b.attitude * dvec3{in(600, 1400), in(-150, 150), in(-100, 100)};
    b.omega = dvec3{in(-1, 1), in(-1, 1), in(-1, 1)};
    b.phase = in(0, 2 * kPi);
    b.frequency = in(sp.f_min, sp.f_max);
    b.amplitude = in(sp.amp_min, sp.amp_max);
    b.tail_bend = in(-sp.bend_max, sp.bend_max);
    b.tail_twist = in(-sp.rot_max, sp.rot_max);
    switch (i % 8) {
      case 5:  // near the ground: ground effect
        b.position.y = in(1, 0.99 * sp.wing_length);
        break;
      case 6:  // taking off: crouching or pushing
        b.mode = FlightMode::taking_off;
        b.mode_time = in(0, sp.crouch_time + sp.leg_time);
        b.position.y = s.world.ground_height + sp.stand_height;
        b.velocity = dvec3{0.0};
        b.omega = dvec3{0.0};
        b.attitude = heading_attitude(heading);
        break;
      case 7: {  // landing: on the curve to the branch, some within the braking distance
        b.route = 1;
        b.target = 0;
        const Branch& br = s.world.branches[0];
        const dvec3 perch = perch_point(sp, br);
        b.position = perch + dvec3{in(-1, 1), in(-0.2, 0.2), in(-1, 1)} * (2.0 * sp.brake_distance);
        b.velocity = glm::normalize(perch - b.position + dvec3{0, 0.01, 0}) * in(500, 1200);
        b.landing_stage = LandingStage::curve;
        b.landing_start = b.position - b.velocity;
        b.via_point = 0.5 * (b.landing_start + perch);
        b.landing_progress = in(0, 1);
        if (u(rng) < 0.5) b.mode = FlightMode::landing;
        break;
      }
      default:
        break;
    }
    birds.push_back(rounded(b));
  }
  return birds;
}

double max_abs(const dvec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

TEST(GpuCrossCheck, OneStepForcesTorquesAndStateMatchTheReference) {
  DEVICE_OR_SKIP(device);
  const Scenario scenario = probe_scenario();
  const std::vector<BirdState> birds = random_birds(scenario, 12000, 7);
  gpu::GpuSimulation gpu_sim(*device, scenario, birds);
  const std::vector<gpu::ProbeForces> gpu_forces = gpu_sim.step_probe();
  const std::vector<BirdState>& gpu_after = gpu_sim.birds();

  World world = scenario.world;
  world.move_targets(0.0);
  double worst_force = 0, worst_torque = 0, worst_position = 0, worst_velocity = 0;
  size_t mode_mismatches = 0;
  for (size_t i = 0; i < birds.size(); ++i) {
    const Species& sp = scenario.species[birds[i].species];
    BirdState cpu = birds[i];
    StepForces f;
    step_bird(cpu, sp, world, 0.0, scenario.dt, &f);
    // Relative to the force (torque) itself plus the weight (the weight at half the span), so
    // that small forces are not held to a tighter absolute bound than float rounding allows.
    const double weight = sp.mass * kGravity;
    const double force_scale = glm::length(f.total) + weight;
    const double torque_scale = glm::length(f.torque) + weight * 0.5 * sp.box_c;
    const double df = max_abs(dvec3(gpu_forces[i].total) - f.total) / force_scale;
    worst_force = std::max(worst_force, df);
    worst_torque = std::max(worst_torque, max_abs(dvec3(gpu_forces[i].torque) - f.torque) / torque_scale);
    worst_position = std::max(worst_position, max_abs(gpu_after[i].position - cpu.position));
    worst_velocity = std::max(worst_velocity, max_abs(gpu_after[i].velocity - cpu.velocity));
    if (gpu_after[i].mode != cpu.mode) ++mode_mismatches;
  }
  RecordProperty("worst_force_relative", std::to_string(worst_force));
  RecordProperty("worst_torque_relative", std::to_string(worst_torque));
  RecordProperty("worst_position_cm", std::to_string(worst_position));
  RecordProperty("worst_velocity_cm_s", std::to_string(worst_velocity));
  // Float rounding: measured 1e-6 (with the shader's precise trigonometry).
  EXPECT_LT(worst_force, 1e-5);
  EXPECT_LT(worst_torque, 1e-5);
  EXPECT_LT(worst_position, 1e-3);  // a step moves a bird about 0.3 cm
  EXPECT_LT(worst_velocity, 1e-2);
  EXPECT_EQ(mode_mismatches, 0u);
  EXPECT_EQ(device->validation_errors(), 0u);
}

// Every built-in scenario for its first 2 simulated seconds on both backends.
class GpuTrajectory : public ::testing::TestWithParam<std::string> {};

TEST_P(GpuTrajectory, FirstTwoSecondsFollowTheReference) {
  DEVICE_OR_SKIP(device);
  const Scenario scenario = load_scenario(GetParam());
  std::vector<BirdState> start = spawn_birds(scenario, std::min<uint32_t>(64, uint32_t(spawn_birds(scenario).size())));
  for (BirdState& b : start) b = rounded(b);
  Simulation cpu(scenario, 0);
  cpu.birds() = start;
  gpu::GpuSimulation gpu_sim(*device, scenario, start);
  while (cpu.time() < 2.0 - 1e-9) {
    cpu.step_frame();
    gpu_sim.step_frame();
  }
  const std::vector<BirdState>& g = gpu_sim.birds();
  double worst = 0;
  for (size_t i = 0; i < g.size(); ++i) worst = std::max(worst, glm::distance(g[i].position, cpu.birds()[i].position));
  RecordProperty("worst_position_difference_cm", std::to_string(worst));
  EXPECT_LT(worst, 20.0) << "1% of the 20 m flown in 2 s";
  EXPECT_EQ(device->validation_errors(), 0u);
}

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const auto& s : builtin_scenarios()) names.push_back(s.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(All, GpuTrajectory, ::testing::ValuesIn(builtin_names()),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

}  // namespace
}  // namespace aeroflock

namespace aeroflock {
namespace {

// The frame before the last one can be read while the last one runs: it is the state after that
// frame, at that frame's time.
TEST(GpuReadback, PreviousFrameIsTheStateOneFrameBack) {
  DEVICE_OR_SKIP(device);
  const Scenario scenario = load_scenario("fig16-circling-eagle");
  gpu::GpuSimulation sim(*device, scenario, 1);
  const double frame = scenario.dt * scenario.steps_per_frame;
  sim.step_frame();
  sim.step_frame();
  const BirdState after_two = sim.birds()[0];
  sim.step_frame();
  EXPECT_NEAR(sim.previous_time(), 2 * frame, 1e-12);
  EXPECT_EQ(sim.previous_birds()[0].position, after_two.position);
  EXPECT_NE(sim.birds()[0].position, after_two.position);
  EXPECT_EQ(device->validation_errors(), 0);
}

}  // namespace
}  // namespace aeroflock
