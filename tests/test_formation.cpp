// Formation flying (issue 43, docs/MODEL.md "Formation flying") on the CPU reference: the phase in
// which a follower's wings meet the most upwash is the leader's wingtip path (Portugal et al.
// 2014's spatial phase), and a follower released off the leader's wake finds the upwash and that
// phase by itself, which it does not without the wake.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "formation_run.h"
#include "io/scenario_file.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/flock.h"
#include "model/formation_figures.h"
#include "model/simulation.h"
#include "model/species.h"

namespace aeroflock {
namespace {

using glm::dvec3;
using testing::formation_scenario;

// A follower `behind` spans behind a leader level with it and `lateral` cm out, both at 10 m/s
// and the species' middle frequency, amplitude 0.8: the upwash its wings meet over a beat
// (upwash_met) in each of 72 phases, the best and the worst as the phase lag less the spatial
// phase 2 pi f dx / U (rad, in [-pi, pi]).
struct PhaseScan {
  double best = -1e30, worst = 1e30;  // cm/s
  double best_from_spatial = 0.0, worst_from_spatial = 0.0;
};
PhaseScan scan_phases(const Species& s, double behind, double lateral) {
  BirdState b;
  b.frequency = 0.5 * (s.f_min + s.f_max);
  b.amplitude = 0.8;
  b.velocity = dvec3{1000.0, 0.0, 0.0};
  b.position = dvec3{-behind * s.box_c, 0.0, lateral};
  Perception p;
  p.wakes = 1;
  p.wake[0].air_velocity = b.velocity;
  p.wake[0].lift = s.mass * kGravity;
  p.wake[0].frequency = b.frequency;
  p.wake[0].amplitude = b.amplitude;
  const double spatial = 2.0 * kPi * b.frequency * behind * s.box_c / 1000.0;
  PhaseScan scan;
  for (int k = 0; k < 72; ++k) {
    const double shift = 2.0 * kPi * k / 72.0;
    const double met = upwash_met(s, b, p, dvec3{0.0, 1.0, 0.0}, dvec3{0.0}, shift);
    // The lag: the leader's phase (0) less the follower's.
    const double from_spatial = std::remainder(-shift - spatial, 2.0 * kPi);
    if (met > scan.best) scan.best = met, scan.best_from_spatial = from_spatial;
    if (met < scan.worst) scan.worst = met, scan.worst_from_spatial = from_spatial;
  }
  return scan;
}

// Outboard of the leader's wake (at the best lateral offset), at 0.5 to 3 spans behind: of 72
// phases, the follower's wings meet the most upwash over a beat when its wingbeat lags the
// leader's by 2 pi f dx / U, within pi / 4: its wingtip then traces the leader's wingtip path.
TEST(Formation, TheBestPhaseOutboardIsTheLeadersWingtipPath) {
  for (const Species& s : {starling(), eagle()}) {
    const double lateral = best_lateral_offset(s, 1.0 * s.box_c);
    RecordProperty(s.name + "_best_lateral_spans", std::to_string(lateral / s.box_c));
    EXPECT_GT(lateral, 0.75 * s.box_c) << s.name;  // the tips overlap a little: vortices pi/4 apart
    EXPECT_LT(lateral, 0.95 * s.box_c) << s.name;
    for (const double behind : {0.5, 1.0, 2.0, 3.0}) {
      const PhaseScan scan = scan_phases(s, behind, lateral);
      std::printf("%s %.1f spans behind, %.3f out: best %+.0f deg from the spatial phase\n",
                  s.name.c_str(), behind, lateral / s.box_c, degrees(scan.best_from_spatial));
      EXPECT_LE(std::fabs(scan.best_from_spatial), kPi / 4.0)
          << s.name << ", " << behind << " spans behind";
      EXPECT_GT(scan.best, 0.0) << "upwash outboard";
    }
  }
}

// Directly behind the leader (in the downwash between its tip vortices), at 0.5 to 3 spans behind:
// of 72 phases, the follower's wings meet the least downwash over a beat when its wingbeat lags
// the leader's by 2 pi f dx / U + pi, within pi / 4: Portugal et al. 2014's spatial anti-phase of
// an ibis directly behind another. The worst is the spatial phase itself, where its wings trace
// the path of the leader's and sweep through the downwash inboard of the vortices. (Sampled at 4
// moments of the beat, the best phase here aliased to anywhere; kBeatSamples is 16.)
TEST(Formation, TheBestPhaseDirectlyBehindIsTheSpatialAntiPhase) {
  for (const Species& s : {starling(), eagle(), ibis(), goose()}) {
    for (const double behind : {0.5, 1.0, 2.0, 3.0}) {
      const PhaseScan scan = scan_phases(s, behind, 0.0);
      std::printf("%s %.1f spans behind: best %+.0f deg from the spatial phase, worst %+.0f\n",
                  s.name.c_str(), behind, degrees(scan.best_from_spatial),
                  degrees(scan.worst_from_spatial));
      EXPECT_GE(std::fabs(scan.best_from_spatial), 0.75 * kPi) << s.name << ", " << behind;
      EXPECT_LE(std::fabs(scan.worst_from_spatial), 0.25 * kPi) << s.name << ", " << behind;
      EXPECT_LT(scan.best, 0.0) << "downwash behind";
    }
  }
}

// In a crosswind a bird crabs: its wings and its wake lie square to its flight through the air,
// not to its track over the ground. A follower set at the V place behind a leader, in the frame of
// their flight through the air, in a crosswind of 4 m/s at 14 m/s (a crab of 16 degrees), is in
// its V place and in phase measured so (`world` given), and out of it measured along the track.
// The probes formation() takes together (upwash_met_at: the places square to the leader's flight
// at once, the phase probes from the bird's own places moments on) give each probe's upwash as
// upwash_met gives it alone: 500 followers behind two birds whose flights cross it by up to 11
// degrees, each wake in turn the leader's.
TEST(Formation, TheProbesTakenTogetherAreEachProbeAlone) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Species& s : {ibis(), starling()}) {
    double worst = 0.0, largest = 0.0;
    for (int n = 0; n < 500; ++n) {
      BirdState b;
      b.frequency = 0.5 * (s.f_min + s.f_max);
      b.amplitude = 0.8;
      b.phase = 3.0 * u(random);
      b.velocity = dvec3{1000.0, 20.0 * u(random), 30.0 * u(random)};
      b.position = dvec3{-s.box_c * (1.5 + u(random)), 10.0 * u(random), 0.8 * s.box_c * u(random)};
      b.attitude = glm::angleAxis(0.1 * u(random),
                                  glm::normalize(dvec3{u(random), u(random), u(random)} + 1e-3));
      Perception p;
      p.wakes = 2;
      for (uint32_t m = 0; m < 2; ++m) {
        WakeSource& w = p.wake[m];
        w.position =
            dvec3{m * s.box_c * (1.0 + 0.5 * u(random)), 5.0 * u(random), m * s.box_c * u(random)};
        w.air_velocity = dvec3{1000.0, 0.0, 200.0 * u(random)};
        w.attitude =
            glm::angleAxis(std::atan2(-w.air_velocity.z, w.air_velocity.x), dvec3{0.0, 1.0, 0.0});
        w.lift = s.mass * kGravity;
        w.frequency = b.frequency * (1.0 + 0.05 * u(random));
        w.amplitude = 0.8;
        w.phase = 3.0 * u(random);
      }
      const uint32_t lead = static_cast<uint32_t>(n % 2);
      const dvec3 ahead = glm::normalize(p.wake[lead].air_velocity);
      const dvec3 side = glm::normalize(glm::cross(ahead, dvec3{0.0, 1.0, 0.0}));
      const dvec3 up = glm::cross(side, ahead);
      const double step = kFormationProbe * s.box_c;
      const dvec3 places[5] = {dvec3{0.0}, -step * side, step * side, -step * up, step * up};
      const BeatPlaces own = beat_places(s, b, 0.0);
      double together[5];
      upwash_met_at(s, b, p, up, own, 0, places, lead, together);
      for (int o = 0; o < 5; ++o) {
        const double alone = upwash_met(s, b, p, up, places[o], 0.0);
        worst = std::max(worst, std::fabs(together[o] - alone));
        largest = std::max(largest, std::fabs(alone));
      }
      for (const int sign : {-1, 1}) {
        double moments_on = 0.0;
        upwash_met_at(s, b, p, up, own,
                      sign > 0 ? kPhaseProbeSamples : kBeatSamples - kPhaseProbeSamples,
                      std::span<const dvec3>(places, 1), 0, std::span<double>(&moments_on, 1));
        worst = std::max(
            worst, std::fabs(moments_on - upwash_met(s, b, p, up, dvec3{0.0}, sign * kPhaseProbe)));
      }
    }
    std::printf("%s: at most %.2g cm/s apart, of upwashes up to %.1f cm/s\n", s.name.c_str(), worst,
                largest);
    EXPECT_GT(largest, 10.0) << s.name;
    EXPECT_LT(worst, 1e-9 * largest) << s.name;
  }
}

TEST(Formation, TheVPlaceIsMeasuredInTheFlightThroughTheAir) {
  const Species s = ibis();
  const double optimum = best_lateral_offset(s, s.box_c);
  World world;
  world.wind = dvec3{0.0, 0.0, 400.0};
  BirdState lead, follower;
  for (BirdState* b : {&lead, &follower}) {
    b->velocity = dvec3{1400.0, 0.0, 0.0} + world.wind;  // heading along x through the air
    b->frequency = 5.0;
  }
  lead.position = dvec3{0.0, 6000.0, 0.0};
  follower.position = lead.position + dvec3{-s.box_c, 0.0, optimum};
  follower.phase = std::remainder(-2.0 * kPi * lead.frequency * s.box_c / 1400.0, 2.0 * kPi);
  if (follower.phase < 0.0) follower.phase += 2.0 * kPi;
  const std::vector<BirdState> birds{lead, follower};
  std::vector<FormationRole> roles;
  const FormationFigures air = formation_figures(birds, s, optimum, &roles, &world);
  EXPECT_EQ(air.followers, 1u);
  EXPECT_EQ(air.in_v, 1u);
  EXPECT_EQ(air.in_phase, 1u);
  ASSERT_EQ(roles.size(), 2u);
  EXPECT_EQ(roles[0], FormationRole::head);
  EXPECT_EQ(roles[1], FormationRole::in_v);
  EXPECT_EQ(formation_figures(birds, s, optimum).in_v, 0u) << "along the track";
}

struct PairFlight {
  double in_v = 0.0;      // share of the samples from 30 s on with the follower in a V place
  double in_phase = 0.0;  // of those, the share in spatial phase
  size_t samples = 0;
  bool finite = true, above_ground = true, upright = true;
};

// A leader and a follower released 2 spans behind it and 1.5 spans to its right, both level at 10
// m/s, the follower's wingbeat `phase` behind the leader's: 60 s, sampled every frame from 30 s on.
PairFlight fly_pair(bool wake, double phase) {
  const Scenario scenario = formation_scenario(2, wake);
  CpuSimulation sim(scenario);
  std::vector<BirdState>& birds = sim.state();
  const Species& s = scenario.species[birds[0].species];
  birds[0].position = dvec3{0.0, 6000.0, 0.0};
  birds[1].position = birds[0].position + dvec3{-2.0 * s.box_c, 0.0, 1.5 * s.box_c};
  for (BirdState& b : birds) {
    b.velocity = dvec3{1000.0, 0.0, 0.0};
    b.attitude = heading_attitude(0.0);
  }
  birds[0].phase = phase;
  birds[1].phase = 0.0;
  const double optimum = best_lateral_offset(s, 1.0 * s.box_c);
  PairFlight f;
  size_t in_v = 0, in_phase = 0;
  while (sim.time() < 60.0 - 1e-9) {
    sim.step_frame();
    for (const BirdState& b : sim.birds()) {
      f.finite = f.finite && all_finite(b);
      f.above_ground = f.above_ground && b.position.y > scenario.world.ground_height;
      f.upright = f.upright && (b.attitude * dvec3{0.0, 1.0, 0.0}).y > 0.0;
    }
    if (sim.time() < 30.0) continue;
    const FormationFigures x = formation_figures(sim.birds(), s, optimum);
    ++f.samples;
    in_v += x.in_v;
    in_phase += x.in_phase;
  }
  f.in_v = double(in_v) / double(f.samples);
  f.in_phase = in_v > 0 ? double(in_phase) / double(in_v) : 0.0;
  return f;
}

// Issue 43's criteria for the followers of a V, on one follower released in four phases: at least
// 70 % of the time at a bearing of 30-60 degrees behind the leader's wing with the lateral spacing
// within 10 % of the optimum, and of that at least 70 % with its wingbeat in spatial phase (within
// pi / 4). With the wake off neither holds: the flock's rules alone may leave it diagonally behind
// (at separation_radius), but nothing times its wingbeat.
TEST(Formation, AFollowerRidesTheUpwashInTheLeadersWingtipPath) {
  double off_in_v = 0.0, off_in_phase = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double phase = 0.5 * kPi * k;
    const PairFlight on = fly_pair(true, phase), off = fly_pair(false, phase);
    std::printf(
        "released %.0f deg behind: with the wake %.2f of %zu frames in a V place, %.2f of "
        "those in spatial phase; without %.2f, %.2f\n",
        degrees(phase), on.in_v, on.samples, on.in_phase, off.in_v, off.in_phase);
    RecordProperty("in_v_" + std::to_string(k), std::to_string(on.in_v));
    RecordProperty("in_phase_" + std::to_string(k), std::to_string(on.in_phase));
    EXPECT_GE(on.in_v, 0.7) << degrees(phase);
    EXPECT_GE(on.in_phase, 0.7) << degrees(phase);
    off_in_v += off.in_v / 4.0;
    off_in_phase += off.in_phase / 4.0;
    for (const PairFlight& f : {on, off}) {
      EXPECT_TRUE(f.finite);
      EXPECT_TRUE(f.above_ground);
      EXPECT_TRUE(f.upright);
    }
  }
  RecordProperty("in_v_without_wake", std::to_string(off_in_v));
  RecordProperty("in_phase_without_wake", std::to_string(off_in_phase));
  EXPECT_LT(off_in_v, 0.7);
  EXPECT_LT(off_in_phase, 0.7);
}

// Issue 43's V from a loose start and its energy (formation_run.h), seeds 1-4: `ibis-v`'s
// followers keep a V place (a bearing of 30-60 degrees behind the wing of the bird they follow,
// their lateral spacing within 10 % of the optimum) 73.6, 77.7, 93.4 and 71.7 % of the time (77.2 %
// over 16 seeds, 53.7-93.4), 89-100 % of that in spatial phase; a follower spends 130-134 W
// against 135.8 W alone (2.5 % less over the 16 seeds); with the wakes off 2 % in V places. Those
// directly behind their leader (seed 1) flap in the spatial anti-phase, with the wakes off in any.
// Before the follower closed on its place by the offset alone (CHANGELOG, issue 43) 66.8 % over
// twelve seeds and 137-148 W: its leader's airspeed and their velocities' difference, read at an
// instant, carried their wingbeats' surge and heave, and the swings grew down a chain.
TEST(Formation, ALooseGroupOfIbisesFormsAVAndItsFollowersSpendLess) {
  testing::expect_ibis_v_forms_a_v_and_saves(
      [](const Scenario& s, std::vector<BirdState> birds) {
        return std::make_unique<CpuSimulation>(s, std::move(birds));
      },
      4, 2, true);
}

// Each of geese-migration's three skeins (24, 32 and 40 greylag geese released as loose groups in
// a crosswind of 4.8 m/s at 300 m, fixed-rate turning), measured as `aeroflock run geese-migration
// --structure-from 60` measures it to 120 s: 79.1, 87.2 and 61.3 % of its followers in V places.
TEST(Formation, TheGeeseSkeinsFlyInV) {
  CpuSimulation sim(load_scenario("geese-migration"));
  const std::vector<FlockStructureSummary> skeins = testing::fly_measured(sim, 60.0, 120.0);
  double mean = 0.0;
  for (const FlockStructureSummary& f : skeins) {
    ASSERT_TRUE(f.formation) << f.flock;
    const double in_v = f.formation->in_v();
    std::printf("%s: %.3f of the followers in a V place, %.3f of those in phase\n", f.flock.c_str(),
                in_v, f.formation->in_phase());
    RecordProperty("in_v_" + f.flock, std::to_string(in_v));
    EXPECT_GE(in_v, 0.5) << f.flock;
    mean += in_v / double(skeins.size());
  }
  EXPECT_EQ(skeins.size(), 3u);
  EXPECT_GE(mean, 0.7);
}

// A loose group in formation holds its route's height (formation_run.h), three seeds.
TEST(Formation, ALooseGroupInFormationHoldsItsRoutesHeight) {
  for (uint64_t seed : {1u, 2u, 3u})
    testing::expect_route_height_held(
        seed, [](const Scenario& s) { return std::make_unique<CpuSimulation>(s); });
}

// Issue 43's energy criterion (formation_run.h).
TEST(Formation, AFollowerSpendsLessPowerThanAlone) {
  testing::expect_a_follower_saves_power([](const Scenario& s, std::vector<BirdState> birds) {
    return std::make_unique<CpuSimulation>(s, std::move(birds));
  });
}

}  // namespace
}  // namespace aeroflock
