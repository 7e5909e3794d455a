// The flight envelope (engine/model/envelope.h): the grid, the judge on flights whose outcome is
// known, each preset's whole grid and the quick grid with moved calibrations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>

#include <glm/geometric.hpp>

#include "model/body.h"
#include "model/constants.h"
#include "model/flock_geometry.h"
#include "run/fly_envelope.h"
#include "touchdown_criteria.h"

namespace aeroflock {
namespace {

SimulationFactory cpu() {
  return [](Scenario s, std::vector<BirdState> birds) -> std::unique_ptr<Simulation> {
    return std::make_unique<CpuSimulation>(std::move(s), std::move(birds));
  };
}

EnvelopeResult fly_one(const Species& s, const EnvelopeCase& c) {
  return fly_envelope(s, {c}, cpu())[0];
}

TEST(Envelope, GridCoversTheIssuesRanges) {
  const std::vector<EnvelopeCase> cases = envelope_cases();
  EXPECT_GE(cases.size(), 1000u);
  double min_speed = 1e9, max_speed = 0, max_rise = -1e9, min_rise = 1e9, max_distance = 0;
  int takeoffs = 0, landings = 0;
  for (const EnvelopeCase& c : cases) {
    if (c.kind == EnvelopeCase::Kind::takeoff) ++takeoffs;
    if (c.kind == EnvelopeCase::Kind::landing) ++landings;
    if (c.kind != EnvelopeCase::Kind::flight) continue;
    min_speed = std::min(min_speed, c.speed), max_speed = std::max(max_speed, c.speed);
    min_rise = std::min(min_rise, c.rise), max_rise = std::max(max_rise, c.rise);
    max_distance = std::max(max_distance, c.distance);
  }
  EXPECT_EQ(min_speed, 500.0);
  EXPECT_EQ(max_speed, 2000.0);
  EXPECT_EQ(max_rise, 5000.0);
  EXPECT_EQ(min_rise, -15000.0);
  EXPECT_EQ(max_distance, 200000.0);
  EXPECT_GT(takeoffs, 0);
  EXPECT_GT(landings, 0);
}

// Issue 43: a species that does not perch lands on a site on the ground (a branch at the ground's
// height): the ibis, straight in across an 8 m/s wind, perches at the site in its first pass and
// then stands there, its feet on the ground (its centre stand_height up), never under it.
TEST(Envelope, AGroundLanderStandsOnTheSite) {
  EnvelopeCase c;
  c.kind = EnvelopeCase::Kind::landing;
  c.rise = -200.0;
  c.distance = 3000.0;
  c.crosswind = 800.0;
  const Species s = ibis();
  EnvelopeFlight flight = envelope_flight(s, {c}, kFastDt);
  const Branch& site = flight.scenario.world.branches.at(0);
  EXPECT_EQ(site.point.y, flight.scenario.world.ground_height);
  CpuSimulation sim(flight.scenario, flight.birds);
  double lowest = 1e9, perched_at = -1.0;
  while (sim.time() < 15.0) {
    sim.step(flight.scenario.steps_per_frame);
    const BirdState& b = sim.state()[0];
    ASSERT_TRUE(is_finite(b));
    lowest = std::min(lowest, b.position.y);
    if (perched_at < 0.0 && b.mode == FlightMode::perched) perched_at = sim.time();
  }
  const BirdState& b = sim.state()[0];
  RecordProperty("perched_at_s", std::to_string(perched_at));
  EXPECT_GT(perched_at, 0.0) << "it perches within 15 s";
  EXPECT_LT(perched_at, 10.0) << "in its first pass (4.9 s)";
  EXPECT_EQ(b.mode, FlightMode::perched);
  EXPECT_NEAR(b.position.y, site.point.y + s.stand_height, 1.0) << "its feet on the ground";
  EXPECT_LE(glm::length(horizontal(b.position - site.point)), s.perch_radius);
  EXPECT_GE(lowest - 0.5 * s.box_b, site.point.y) << "its body never under the ground";
}

TEST(Envelope, JudgesAReachedTargetAndASpeciesThatCannotFly) {
  EnvelopeCase easy;  // level at cruise, the target 50 m straight ahead and 5 m down
  easy.speed = 1000.0;
  easy.rise = -500.0;
  easy.distance = 5000.0;
  EnvelopeCase climb = easy;  // 20 m up
  climb.rise = 2000.0;
  const std::vector<EnvelopeResult> r = fly_envelope(starling(), {easy, climb}, cpu());
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].outcome, Outcome::reached) << name(r[0].outcome);
  EXPECT_LT(r[0].time, 10.0);
  EXPECT_EQ(r[1].outcome, Outcome::reached) << name(r[1].outcome);
  // Five times as heavy on the same wings: it cannot climb, nor hold its height.
  Species heavy = starling();
  heavy.mass *= 5.0;
  const std::vector<EnvelopeResult> h = fly_envelope(heavy, {easy, climb}, cpu());
  EXPECT_NE(h[1].outcome, Outcome::reached) << name(h[1].outcome);
}

// Each landing's grip is watched (issue 40's measures, model/touchdown.h): the touch-down on the
// branch when it perched, its window a wingbeat or 100 ms, and the bird followed for kSettleWatch
// after it before it is retired.
TEST(Envelope, EachLandingsGripIsWatched) {
  std::vector<EnvelopeCase> landings;
  for (const EnvelopeCase& c : envelope_cases())
    if (c.kind == EnvelopeCase::Kind::landing && c.crosswind == 0.0 && landings.size() < 6)
      landings.push_back(c);
  ASSERT_EQ(landings.size(), 6u);
  const Species s = starling();
  for (const EnvelopeResult& r : fly_envelope(s, landings, cpu(), {}, kFastDt)) {
    ASSERT_EQ(r.outcome, Outcome::reached) << r.c.describe();
    ASSERT_TRUE(r.touchdown.has_value()) << r.c.describe();
    const Touchdown& d = *r.touchdown;
    EXPECT_TRUE(d.on_branch);
    EXPECT_NEAR(d.time, r.time, 1e-9) << "the grip is the landing's outcome";
    EXPECT_NEAR(d.window, std::max(1.0 / s.f_max, kTouchdownWindow), 0.5 / s.f_min);
    EXPECT_GT(d.mean_speed, 0.0);
    EXPECT_LE(d.mean_speed, 2.0 * s.touchdown_speed);
    EXPECT_GT(d.speed_fall, 0.0);
  }
}

// Issue 10: an eagle 30 % lighter than the preset spirals up to a target 50 m above and 50 m away
// and then circled it at its height for 15 s, the target 4 m from the centre of its 15 m circle,
// never passing within three radii. Now it flies off on level wings and turns onto it.
TEST(Envelope, AnEagleDoesNotCircleItsTargetForEver) {
  Species light = eagle();
  light.mass *= 0.7;
  const EnvelopeResult r = fly_one(light, {.speed = 500.0,
                                           .pitch = radians(-30.0),
                                           .bank = radians(-60.0),
                                           .rise = 5000.0,
                                           .bearing = radians(90.0),
                                           .distance = 5000.0});
  EXPECT_EQ(r.outcome, Outcome::reached) << name(r.outcome) << " at " << r.time << " s";
}

// Issue 10: an eagle 30 % heavier than the preset, spiralling down onto a target 150 m below and
// 50 m away, reversed its bank each time the target, passing beneath it, crossed its tail, and
// pitched to 60.8 degrees in a reversal. Now it turns on the way it banks (control.h: turn_on).
TEST(Envelope, AHeavyEagleSpiralsDownOntoATargetBeneathIt) {
  Species heavy = eagle();
  heavy.mass *= 1.3;
  const EnvelopeResult r = fly_one(heavy, {.speed = 2000.0,
                                           .pitch = radians(-30.0),
                                           .rise = -15000.0,
                                           .bearing = radians(90.0),
                                           .distance = 5000.0});
  EXPECT_EQ(r.outcome, Outcome::reached) << name(r.outcome) << " at " << r.time << " s";
  EXPECT_LT(degrees(r.worst_pitch), 50.0);
}

// Issue 10: the same heavy eagle started at 20 m/s, pitched 30 degrees down and banked 60, to a
// target 50 m below and 50 m away: it glided down with its wings still, began to beat them only at
// the target's height, sank 19 m under it while the amplitude rose from 0, and arrived after the
// 30.6 s allowed. Now its wingbeat looks ahead by what it sinks meanwhile (control.h: spool_lead):
// it arrives in 9.0 s, 1 m above the target's centre at its lowest.
TEST(Envelope, AHeavyEagleGlidingDownBeatsInTimeToHoldTheTargetsHeight) {
  Species heavy = eagle();
  heavy.mass *= 1.3;
  const EnvelopeResult r = fly_one(heavy, {.speed = 2000.0,
                                           .pitch = radians(-30.0),
                                           .bank = radians(-60.0),
                                           .rise = -5000.0,
                                           .bearing = radians(90.0),
                                           .distance = 5000.0});
  EXPECT_EQ(r.outcome, Outcome::reached) << name(r.outcome) << " at " << r.time << " s";
  EXPECT_LT(r.time, 15.0);
  EXPECT_GT(r.lowest, 20000.0 - 5000.0 - 300.0) << "sank under the target's sphere (3 m)";
  EXPECT_LT(degrees(r.worst_pitch), 50.0);
}

// Issue 10: each preset flies every case of the grid (1,692 flights, take-offs and branch
// landings (the ibis: on the ground, ground_landing), crosswinds of 0, 5 and 8 m/s) on the CPU
// reference, within the limits throughout, and each first touch-down, on a branch or the ground,
// without a jump (issue 40: touchdown_criteria.h). One test per preset and crosswind (564 cases
// each), so that ctest spreads them over the cores.
struct GridPart {
  Species (*preset)();
  double crosswind;  // cm/s
  double dt = kPaperDt;
};
void PrintTo(const GridPart& p, std::ostream* os) {
  *os << p.preset().name << " " << p.crosswind << " cm/s, dt " << p.dt << " s";
}

class WholeGrid : public ::testing::TestWithParam<GridPart> {};

TEST_P(WholeGrid, EveryCaseSucceeds) {
  const Species species = GetParam().preset();
  std::vector<EnvelopeCase> cases;
  for (const EnvelopeCase& c : envelope_cases())
    if (c.crosswind == GetParam().crosswind) cases.push_back(c);
  ASSERT_EQ(cases.size(), 564u);
  size_t reached = 0;
  double worst_bank = 0.0, worst_pitch = 0.0;
  double jump = 0.0, before = 0.0;  // the landings' grips (issue 40): the largest
  size_t ground_landings = 0, ground_perched = 0;
  for (const EnvelopeResult& r : fly_envelope(species, cases, cpu(), {}, GetParam().dt)) {
    reached += r.outcome == Outcome::reached;
    if (ground_landing(r, species)) {
      ++ground_landings;
      ground_perched += r.outcome == Outcome::reached;
    }
    if (r.touchdown && !ground_landing(r, species)) {
      jump = std::max(jump, r.touchdown->jump);
      before = std::max(before, r.touchdown->mean_speed);
    }
    worst_bank = std::max(worst_bank, r.worst_bank);
    worst_pitch = std::max(worst_pitch, r.worst_pitch);
    EXPECT_EQ(r.outcome, Outcome::reached) << r.c.describe() << ": " << name(r.outcome);
    expect_smooth_touchdown(r, species);
  }
  RecordProperty("reached", std::to_string(reached) + " of " + std::to_string(cases.size()));
  RecordProperty("worst_bank_deg", std::to_string(degrees(worst_bank)));
  RecordProperty("worst_pitch_deg", std::to_string(degrees(worst_pitch)));
  RecordProperty("worst_grip_jump_cm", std::to_string(jump));
  RecordProperty("worst_speed_before_grip_m_s", std::to_string(before / 100.0));
  if (ground_landings > 0)
    RecordProperty("ground_landings_perched",
                   std::to_string(ground_perched) + " of " + std::to_string(ground_landings));
}

std::string grid_part_name(const ::testing::TestParamInfo<GridPart>& info) {
  return info.param.preset().name + "_wind_" + std::to_string(int(info.param.crosswind / 100.0)) +
         "_m_s";
}
INSTANTIATE_TEST_SUITE_P(Envelope, WholeGrid,
                         ::testing::Values(GridPart{starling, 0.0}, GridPart{starling, 500.0},
                                           GridPart{starling, 800.0}, GridPart{eagle, 0.0},
                                           GridPart{eagle, 500.0}, GridPart{eagle, 800.0}),
                         grid_part_name);
// Issue 13: the whole grid at the fast fidelity's step too (docs/convergence.md). Issue 43: the
// migrants' at the fast step, at which their flocks fly (their landings on the ground,
// ground_landing); at the paper's, docs/VALIDATION.md. Issue 41: the real starling's, at the step
// its murmuration flies.
INSTANTIATE_TEST_SUITE_P(
    FastEnvelope, WholeGrid,
    ::testing::Values(GridPart{starling, 0.0, kFastDt}, GridPart{starling, 500.0, kFastDt},
                      GridPart{starling, 800.0, kFastDt}, GridPart{eagle, 0.0, kFastDt},
                      GridPart{eagle, 500.0, kFastDt}, GridPart{eagle, 800.0, kFastDt},
                      GridPart{ibis, 0.0, kFastDt}, GridPart{ibis, 500.0, kFastDt},
                      GridPart{ibis, 800.0, kFastDt}, GridPart{goose, 0.0, kFastDt},
                      GridPart{goose, 500.0, kFastDt}, GridPart{goose, 800.0, kFastDt},
                      GridPart{european_starling, 0.0, kFastDt},
                      GridPart{european_starling, 500.0, kFastDt},
                      GridPart{european_starling, 800.0, kFastDt}),
    grid_part_name);

// Issue 10: the envelope does not rest on single calibrated values. Every fifth flight of the
// grid (324) and every take-off and landing (72) still succeed with the shoulder 2 cm further
// forward or back, the mass 30 % lighter or heavier and the lead-lag 3 degrees smaller or larger:
// the starling under all six changes, the eagle under four (two more, 2.5 minutes each, would take
// the suite past 30 minutes). One test per preset and change, so that ctest spreads them over the
// cores. All twelve whole grids (1,692 cases a change) succeed, flown with `aeroflock envelope`
// (docs/VALIDATION.md "Flight envelope"); the near, steep descents where the eagle failed last are
// mostly not in this sample (AHeavyEagleGlidingDownBeatsInTimeToHoldTheTargetsHeight flies one). At
// the fast fidelity's step they do not all succeed (docs/convergence.md: 11 of the 4,752 cases
// over-pitch, under four of the twelve changes), so they are flown at the paper's.
struct MovedCalibration {
  Species (*preset)();
  const char* what;
  void (*apply)(Species&);
};
void PrintTo(const MovedCalibration& m, std::ostream* os) {
  *os << m.preset().name << " " << m.what;
}

class MovedCalibrations : public ::testing::TestWithParam<MovedCalibration> {};

TEST_P(MovedCalibrations, StillFliesTheGrid) {
  const std::vector<EnvelopeCase> cases = envelope_sample(5, INFINITY);
  ASSERT_EQ(cases.size(), 396u);
  Species s = GetParam().preset();
  GetParam().apply(s);
  // The hovering final is calibrated for each preset as it is: moved, it flares (hovering, 0-14 of
  // the starling's 16 landings in calm air perched, and 41-44 of the eagle's 48 with its mass or
  // its lead-lag moved: docs/MODEL.md "The hovering final"), the eagle at its flare's incidence of
  // 26 degrees (15 when it was calibrated on the flare).
  s.hover_final = 0;
  for (const EnvelopeResult& r : fly_envelope(s, cases, cpu()))
    EXPECT_EQ(r.outcome, Outcome::reached)
        << GetParam().what << ": " << r.c.describe() << ": " << name(r.outcome);
}

void shoulder_forward(Species& s) { s.shoulder_x += 2.0; }
void shoulder_back(Species& s) { s.shoulder_x -= 2.0; }
void heavier(Species& s) { s.mass *= 1.3; }
void lighter(Species& s) { s.mass *= 0.7; }
void more_leadlag(Species& s) { s.C_leadlag += radians(3.0); }
void less_leadlag(Species& s) { s.C_leadlag -= radians(3.0); }

INSTANTIATE_TEST_SUITE_P(
    Envelope, MovedCalibrations,
    ::testing::Values(MovedCalibration{starling, "shoulder_plus_2_cm", shoulder_forward},
                      MovedCalibration{starling, "shoulder_minus_2_cm", shoulder_back},
                      MovedCalibration{starling, "mass_plus_30_percent", heavier},
                      MovedCalibration{starling, "mass_minus_30_percent", lighter},
                      MovedCalibration{starling, "leadlag_plus_3_deg", more_leadlag},
                      MovedCalibration{starling, "leadlag_minus_3_deg", less_leadlag},
                      MovedCalibration{eagle, "shoulder_plus_2_cm", shoulder_forward},
                      MovedCalibration{eagle, "mass_minus_30_percent", lighter},
                      MovedCalibration{eagle, "leadlag_plus_3_deg", more_leadlag},
                      MovedCalibration{eagle, "leadlag_minus_3_deg", less_leadlag}),
    [](const auto& info) { return info.param.preset().name + "_" + info.param.what; });

}  // namespace
}  // namespace aeroflock
