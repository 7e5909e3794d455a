// Formation flying (issue 43, docs/MODEL.md "Formation flying"): a formation species' flock for
// the tests (tests/test_formation.cpp, tests/test_flock_vulkan.cpp); the place where its wing meets
// the most upwash and the figures of Portugal et al. 2014 are model/formation_figures.h's.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "io/scenario_file.h"
#include "model/body.h"
#include "model/formation_figures.h"
#include "model/simulation.h"
#include "run/run_loop.h"
#include "run/structure.h"

namespace aeroflock::testing {

// `count` birds of `species` (a preset, or one `species_toml` defines) flocking on a straight 3 km
// leg 60 m up, released `extent` cm across, their wakes on (`wake`); turning by the paper's tail
// model or at a fixed rate (`fixed_rate`, eq. 3).
inline Scenario leg_scenario(const std::string& species_toml, const std::string& species,
                             uint32_t count, bool wake, uint32_t seed, double extent,
                             bool fixed_rate = false) {
  const std::string text = "[simulation]\nfidelity = \"fast\"\nduration = 300.0\nseed = " +
                           std::to_string(seed) + "\n" +
                           (fixed_rate ? "turning = \"fixed-rate\"\n" : "") + species_toml + R"(
[[targets]]
name = "end"
centre = [300000.0, 6000.0, 0.0]
radius = 3000.0
[[routes]]
name = "leg"
targets = ["end"]
[[flocks]]
species = ")" + species + R"("
route = "leg"
count = )" + std::to_string(count) +
                           "\ncentre = [0.0, 6000.0, 0.0]\nextent = [" + std::to_string(extent) +
                           ", 100.0, " + std::to_string(extent) +
                           "]\nflocking = true\nwake = " + (wake ? "true" : "false") + "\n";
  return parse_scenario(text, "leg.toml");
}

// `count` eagles that fly in formation (w_formation), released as a loose group 60 m across on a
// straight 3 km leg, their wakes on (`wake`). Separation 1.2 spans: a follower keeps that from
// the bird it follows. They turn at a fixed rate, as the migrants' scenarios do (with the tail
// model a follower's small corrections slip it: a follower released 270 degrees behind kept its V
// place 61 % of the time, against 81 %).
inline Scenario formation_scenario(uint32_t count, bool wake, uint32_t seed = 3) {
  return leg_scenario(R"([[species]]
name = "formation-eagle"
base = "eagle"
w_formation = 8.0
separation_radius = 264.0
w_separation = 2.0)",
                      "formation-eagle", count, wake, seed, 3000.0, true);
}

// A loose group in formation holds its route's height (kFormationRouteHeight; issue 43):
// `ibis-v`'s 14 ibises, released 60 m up on a level route, in seed `seed`, flown by `make` (a
// Simulation for a scenario) to 120 s. From 30 s the flock's mean height is within 7.5 m of the
// route's on average and never 15 m from it; every bird stays finite. Before, nearly every bird
// followed another and none held the route's height: the group drifted up, 21.6-50.3 m at worst
// (then on average 1.2-4.6 m above it and 2.6-9.9 m at worst on either backend; the same group
// without wakes 1.8-2.7 and 3.1-4.3 m; with the head of the formation and the speed lead, within
// 0.1 m on average and 0.2-0.8 m at worst).
template <class Make>
void expect_route_height_held(uint64_t seed, const Make& make) {
  Scenario scenario = load_scenario("ibis-v");
  scenario.seed = seed;
  const double route = scenario.world.targets.front().centre.y;
  std::unique_ptr<Simulation> sim = make(scenario);
  double worst = 0.0, sum = 0.0;
  size_t frames = 0;
  bool finite = true;
  while (sim->time() < 120.0 - 1e-9) {
    sim->step_frame();
    double mean = 0.0;
    for (const BirdState& b : sim->birds()) {
      finite = finite && all_finite(b);
      mean += b.position.y / double(sim->birds().size());
    }
    if (sim->time() < 30.0) continue;
    worst = std::max(worst, std::fabs(mean - route));
    sum += mean - route, ++frames;
  }
  const double mean = sum / double(frames);
  std::printf(
      "seed %lu: the flock's mean height %.1f m above its route's, 30-120 s, at most %.1f "
      "m from it\n",
      (unsigned long)seed, mean / 100.0, worst / 100.0);
  ::testing::Test::RecordProperty("mean_m_" + std::to_string(seed), std::to_string(mean / 100.0));
  ::testing::Test::RecordProperty("worst_m_" + std::to_string(seed), std::to_string(worst / 100.0));
  EXPECT_TRUE(finite) << "seed " << seed;
  EXPECT_LT(std::fabs(mean), 750.0) << "seed " << seed;
  EXPECT_LT(worst, 1500.0) << "seed " << seed;
}

// Issue 43's energy criterion, on the `ibis` preset as ibis-v flies it (fixed-rate turning; with
// the tail model its follower kept a V place 59 % of the time, against 100 %): a pair released
// level at cruise on leg_scenario's leg, the follower 2 spans behind the leader and 1.5 spans to
// its right (`count` 2), or the leader's start alone (`count` 1). From 30 to 90 s (each frame's
// next step): each bird's mean aerodynamic power and airspeed, and for the follower the mean upwash
// its wings meet and its share of frames in a V place (formation_figures.h).
struct PairPower {
  double power_w[2] = {0.0, 0.0};  // leader, follower (W)
  double speed[2] = {0.0, 0.0};    // cm/s
  double upwash = 0.0;             // the follower's, cm/s
  double in_v = 0.0;               // the follower's
  bool finite = true, upright = true;
};

template <class Make>
PairPower fly_ibis_pair(uint32_t count, bool wake, const Make& make) {
  const Scenario scenario = leg_scenario("", "ibis", count, wake, 3, 100.0, true);
  std::vector<BirdState> birds = spawn_birds(scenario);
  const Species& s = scenario.species[birds[0].species];
  for (BirdState& b : birds) {
    b.position = glm::dvec3{0.0, 6000.0, 0.0};
    b.velocity = glm::dvec3{s.cruise_speed, 0.0, 0.0};
    b.attitude = heading_attitude(0.0);
    b.phase = 0.0;
  }
  if (count > 1) birds[1].position += glm::dvec3{-2.0 * s.box_c, 0.0, 1.5 * s.box_c};
  std::unique_ptr<Simulation> sim = make(scenario, birds);
  const double optimum = best_lateral_offset(s, 1.0 * s.box_c);
  PairPower p;
  size_t frames = 0, in_v = 0;
  while (sim->time() < 90.0 - 1e-9) {
    const bool record = sim->time() >= 30.0 - 1e-9;
    sim->step_frame(record);
    const Snapshot snap = sim->snapshot();
    for (const BirdState& b : *snap.birds) {
      p.finite = p.finite && all_finite(b);
      p.upright = p.upright && (b.attitude * glm::dvec3{0.0, 1.0, 0.0}).y > 0.0;
    }
    if (!record) continue;
    ++frames;
    for (uint32_t k = 0; k < count; ++k) {
      p.power_w[k] += (*snap.forces)[k].power * 1e-7;
      p.speed[k] += glm::length((*snap.birds)[k].velocity);
    }
    if (count > 1) {
      p.upwash += (*snap.forces)[1].wake_air.y;
      in_v += formation_figures(*snap.birds, s, optimum).in_v;
    }
  }
  for (uint32_t k = 0; k < 2; ++k) p.power_w[k] /= double(frames), p.speed[k] /= double(frames);
  p.upwash /= double(frames);
  p.in_v = double(in_v) / double(frames);
  return p;
}

// Its criterion: the follower of a pair with wakes flies in a V place most of the time and spends
// less than the same bird alone at the same airspeed; without the wakes it saves nothing.
template <class Make>
void expect_a_follower_saves_power(const Make& make) {
  const PairPower alone = fly_ibis_pair(1, true, make);
  const PairPower on = fly_ibis_pair(2, true, make), off = fly_ibis_pair(2, false, make);
  const double saving = 1.0 - on.power_w[1] / alone.power_w[0];
  const double saving_off = 1.0 - off.power_w[1] / alone.power_w[0];
  std::printf(
      "alone %.2f W at %.2f m/s; with the wakes the leader %.2f W, the follower %.2f W at %.2f "
      "m/s (%.1f %% less, its wings meeting %.1f cm/s of upwash, %.0f %% of the time in a V "
      "place); without, the follower %.2f W (%.1f %% less)\n",
      alone.power_w[0], alone.speed[0] / 100.0, on.power_w[0], on.power_w[1], on.speed[1] / 100.0,
      100.0 * saving, on.upwash, 100.0 * on.in_v, off.power_w[1], 100.0 * saving_off);
  ::testing::Test::RecordProperty("alone_w", std::to_string(alone.power_w[0]));
  ::testing::Test::RecordProperty("follower_w", std::to_string(on.power_w[1]));
  ::testing::Test::RecordProperty("saving_percent", std::to_string(100.0 * saving));
  ::testing::Test::RecordProperty("saving_without_wakes_percent",
                                  std::to_string(100.0 * saving_off));
  for (const PairPower& p : {alone, on, off}) {
    EXPECT_TRUE(p.finite);
    EXPECT_TRUE(p.upright);
  }
  EXPECT_NEAR(on.speed[1], alone.speed[0], 10.0);  // the same airspeed, within 0.1 m/s
  EXPECT_GE(on.in_v, 0.5);  // in a V place most of the time (100 %; the V test proper is
                            // test_formation.cpp's, at 0.7)
  EXPECT_GT(on.upwash, 0.0);
  EXPECT_GT(saving, 0.0);
  EXPECT_LE(saving_off, 0.0);
}

// Flies `sim` to `to` s, measured from `from` s a snapshot a second as `aeroflock run
// --structure-from` measures it (run/structure.h): its flocks' figures.
inline std::vector<FlockStructureSummary> fly_measured(Simulation& sim, double from, double to) {
  StructureObserver structure({from, to, 1.0});
  RunLimits limits;
  limits.frames = uint64_t(std::llround(to / sim.scenario().frame_seconds()));
  const RunResult run = run_frames(sim, {&structure}, limits);
  EXPECT_TRUE(run.errors.empty()) << (run.errors.empty() ? "" : run.errors[0]);
  return structure.flocks();
}

// `ibis-v` (14 ibises released as a loose group, the paper's fixed-rate turning) from `seed`, its
// wakes on or off, measured as `aeroflock run ibis-v --structure-from 60` measures it
// (run/structure.h) to 120 s: the share of its followers in a V place and of those in spatial phase
// (a snapshot a second), and the wings' power of a follower and of a head (every frame).
struct GroupFormation {
  double in_v = 0.0, in_phase = 0.0, follower_w = 0.0, head_w = 0.0;
  size_t behind = 0, anti_phase = 0;  // follower-snapshots directly behind, of those in anti-phase
};
template <class Make>
GroupFormation fly_ibis_v(uint64_t seed, bool wake, const Make& make) {
  Scenario scenario = load_scenario("ibis-v");
  scenario.seed = seed;
  for (Flock& f : scenario.flocks) f.wake = wake;
  std::unique_ptr<Simulation> sim = make(scenario, spawn_birds(scenario));
  const FormationMean& f = *fly_measured(*sim, 60.0, 120.0).at(0).formation;
  return {f.in_v(),         f.in_phase(), f.follower_power_w(),
          f.head_power_w(), f.sum.behind, f.sum.anti_phase};
}

// Issue 43's V and energy criteria on `ibis-v`, seeds 1-4 (`flies_seeds`): at least 70 % of the
// followers in a V place over the seeds, most of those in phase, and a follower spends less than
// the same ibis alone at the same airspeed (fly_ibis_pair's, at the scenario's cruise) in each
// seed, while the formation's heads spend as one alone; with the wakes off (`seeds_off`) no V.
// Of the followers directly behind their leader, over the seeds, where `anti_phase_checked` (at
// least 20 follower-snapshots: seed 1 has 121 on the CPU, seeds 2-4 none), at least 70 % in the
// spatial anti-phase (Portugal et al.'s); with the wakes off less than half (in no particular
// phase, a quarter).
template <class Make>
void expect_ibis_v_forms_a_v_and_saves(const Make& make, uint64_t seeds, uint64_t seeds_off,
                                       bool anti_phase_checked) {
  const double alone = fly_ibis_pair(1, true, make).power_w[0];
  double in_v = 0.0, saving = 0.0;
  size_t behind = 0, anti_phase = 0, behind_off = 0, anti_phase_off = 0;
  for (uint64_t seed = 1; seed <= seeds; ++seed) {
    const GroupFormation on = fly_ibis_v(seed, true, make);
    std::printf(
        "seed %llu: %.3f of the followers in a V place, %.3f of those in phase; %zu directly "
        "behind, %zu of those in anti-phase; a follower %.2f W, a head %.2f W, one alone %.2f W\n",
        static_cast<unsigned long long>(seed), on.in_v, on.in_phase, on.behind, on.anti_phase,
        on.follower_w, on.head_w, alone);
    behind += on.behind, anti_phase += on.anti_phase;
    const std::string n = std::to_string(seed);
    ::testing::Test::RecordProperty("in_v_seed_" + n, std::to_string(on.in_v));
    ::testing::Test::RecordProperty("follower_w_seed_" + n, std::to_string(on.follower_w));
    in_v += on.in_v / double(seeds);
    saving += (1.0 - on.follower_w / alone) / double(seeds);
    EXPECT_GE(on.in_v, 0.55) << "seed " << seed;
    EXPECT_GE(on.in_phase, 0.7) << "seed " << seed;
    EXPECT_LT(on.follower_w, alone) << "seed " << seed;
    EXPECT_NEAR(on.head_w, alone, 0.01 * alone) << "seed " << seed;
  }
  ::testing::Test::RecordProperty("alone_w", std::to_string(alone));
  ::testing::Test::RecordProperty("in_v_mean", std::to_string(in_v));
  ::testing::Test::RecordProperty("saving_percent_mean", std::to_string(100.0 * saving));
  EXPECT_GE(in_v, 0.7);
  EXPECT_GE(saving, 0.01);
  for (uint64_t seed = 1; seed <= seeds_off; ++seed) {
    const GroupFormation off = fly_ibis_v(seed, false, make);
    std::printf(
        "wakes off, seed %llu: %.3f in a V place, %zu directly behind, %zu of those in "
        "anti-phase; a follower %.2f W\n",
        static_cast<unsigned long long>(seed), off.in_v, off.behind, off.anti_phase,
        off.follower_w);
    behind_off += off.behind, anti_phase_off += off.anti_phase;
    EXPECT_LT(off.in_v, 0.1) << "wakes off, seed " << seed;
    EXPECT_GE(off.follower_w, alone) << "wakes off, seed " << seed;
  }
  ::testing::Test::RecordProperty("behind", std::to_string(behind));
  ::testing::Test::RecordProperty("anti_phase", std::to_string(anti_phase));
  if (anti_phase_checked) {
    EXPECT_GE(behind, 20u);
    EXPECT_GE(double(anti_phase), 0.7 * double(behind));
    EXPECT_LT(double(anti_phase_off), 0.5 * double(behind_off));
  }
}

}  // namespace aeroflock::testing
