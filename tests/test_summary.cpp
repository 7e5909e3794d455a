// Run summaries: statistics of hand-made bird states and the JSON file; the flock's extent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/scenario_file.h"
#include "io/summary.h"
#include "model/constants.h"
#include "model/flock_geometry.h"

namespace aeroflock {
namespace {

BirdState bird(glm::dvec3 position, glm::dvec3 velocity, FlightMode mode = FlightMode::flying) {
  BirdState b;
  b.position = position;
  b.velocity = velocity;
  b.mode = mode;
  return b;
}

TEST(FlockStatistics, NoBirdsGivesZeros) {
  const FlockStatistics s = flock_statistics({}, {});
  EXPECT_EQ(s.birds, 0u);
  EXPECT_EQ(s.nan_birds, 0u);
  EXPECT_EQ(s.centroid, glm::dvec3(0.0));
  EXPECT_EQ(s.mean_speed, 0.0);
}

TEST(FlockStatistics, CentroidSpeedAndCounts) {
  std::vector<BirdState> birds = {
      bird({0, 0, 0}, {300, 0, 0}),
      bird({200, 100, 0}, {0, 400, 0}, FlightMode::landing),
      bird({100, 200, 600}, {0, 0, 0}, FlightMode::perched),
      bird({0, 0, 0}, {0, 0, 0}, FlightMode::standing),
  };
  birds[0].targets_reached = 2;
  birds[2].targets_reached = 3;
  const FlockStatistics s = flock_statistics(birds, {});
  EXPECT_EQ(s.birds, 4u);
  EXPECT_EQ(s.nan_birds, 0u);
  EXPECT_DOUBLE_EQ(s.centroid.x, 75.0);
  EXPECT_DOUBLE_EQ(s.centroid.y, 75.0);
  EXPECT_DOUBLE_EQ(s.centroid.z, 150.0);
  EXPECT_DOUBLE_EQ(s.mean_speed, 175.0);
  EXPECT_EQ(s.targets_reached, 5u);
  EXPECT_EQ(s.perched, 1u);
  EXPECT_EQ(s.landed, 0u);
  EXPECT_EQ(s.flying, 2u);  // flying and landing; not perched or standing
}

// A bird at rest on its site has perched on a branch, or landed there on the ground if its
// species does not perch (a goose on a field is not "perched").
TEST(FlockStatistics, ABirdAtRestOnTheGroundHasLandedNotPerched) {
  const std::vector<Species> species = {starling(), goose()};
  std::vector<BirdState> birds = {
      bird({0, 100, 0}, {0, 0, 0}, FlightMode::perched),
      bird({0, 20, 0}, {0, 0, 0}, FlightMode::perched),
      bird({0, 20, 500}, {0, 0, 0}, FlightMode::perched),
      bird({0, 20, 900}, {0, 0, 0}, FlightMode::standing),
  };
  birds[1].species = birds[2].species = birds[3].species = 1;
  const FlockStatistics s = flock_statistics(birds, species);
  EXPECT_EQ(s.perched, 1u);
  EXPECT_EQ(s.landed, 2u);
  EXPECT_EQ(s.flying, 0u);
  RunSummary r;
  r.stats = s;
  const nlohmann::ordered_json j = summary_json(r);
  EXPECT_EQ(j["perched"], 1);
  EXPECT_EQ(j["landed"], 2);
}

TEST(FlockStatistics, NonFiniteBirdsAreCountedAndLeftOut) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<BirdState> birds = {
      bird({100, 0, 0}, {100, 0, 0}),
      bird({nan, 0, 0}, {100, 0, 0}),
      bird({0, 0, 0}, {0, inf, 0}),
      bird({300, 0, 0}, {300, 0, 0}),
  };
  birds.push_back(birds[0]);
  birds.back().attitude.w = nan;
  const FlockStatistics s = flock_statistics(birds, {});
  EXPECT_EQ(s.birds, 5u);
  EXPECT_EQ(s.nan_birds, 3u);
  EXPECT_DOUBLE_EQ(s.centroid.x, 200.0);
  EXPECT_DOUBLE_EQ(s.mean_speed, 200.0);
}

// NaN quarantine: a quarantined bird's state is finite (its last finite one) but it counts as a
// NaN bird and is left out of the figures; the summary lists the quarantined, earliest first.
TEST(FlockStatistics, QuarantinedBirdsAreCountedListedAndLeftOut) {
  std::vector<BirdState> birds = {
      bird({100, 0, 0}, {100, 0, 0}),
      bird({900, 0, 0}, {900, 0, 0}, FlightMode::quarantined),
      bird({300, 0, 0}, {300, 0, 0}),
      bird({700, 0, 0}, {700, 0, 0}, FlightMode::quarantined),
      bird({800, 0, 0}, {800, 0, 0}, FlightMode::quarantined),
  };
  birds[1].quarantined_step = 4000;  // 2 s of 0.5 ms steps
  birds[3].quarantined_step = 2000;
  birds[4].quarantined_step = 4000;
  const FlockStatistics s = flock_statistics(birds, {});
  EXPECT_EQ(s.nan_birds, 3u);
  EXPECT_EQ(s.flying, 2u);
  EXPECT_DOUBLE_EQ(s.centroid.x, 200.0);
  EXPECT_DOUBLE_EQ(s.mean_speed, 200.0);
  const std::vector<QuarantinedBird> listed = quarantined_birds(birds, 0.0005, 2);
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[0].bird, 3u);
  EXPECT_EQ(listed[1].bird, 1u);  // of two at 2 s, the lower index
  EXPECT_EQ(listed[1].step, 4000u);
  EXPECT_EQ(listed[1].time, 2.0);
  EXPECT_EQ(listed[1].last.position.x, 900.0);
  RunSummary r;
  r.quarantined = listed;
  const nlohmann::ordered_json j = summary_json(r)["quarantined"];
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["bird"], 3);
  EXPECT_EQ(j[0]["step"], 2000);
  EXPECT_EQ(j[0]["time"], 1.0);
  EXPECT_EQ(j[0]["position"], nlohmann::json::array({700.0, 0.0, 0.0}));
  EXPECT_EQ(j[0]["velocity"], nlohmann::json::array({700.0, 0.0, 0.0}));
  EXPECT_EQ(j[0]["attitude"], nlohmann::json::array({1.0, 0.0, 0.0, 0.0}));
}

TEST(FlockExtent, CentreVelocityAndRadiiOfTheFiniteBirds) {
  EXPECT_EQ(flock_extent({}).finite, 0u);
  EXPECT_EQ(flock_extent({}).centre, glm::dvec3(0.0));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<BirdState> birds = {
      bird({100, 0, 0}, {10, 0, 0}),   bird({nan, 0, 0}, {0, 0, 0}),  bird({300, 0, 0}, {30, 0, 0}),
      bird({200, 50, 0}, {0, nan, 0}), bird({200, 0, 0}, {20, 0, 0}),
  };
  const FlockExtent e = flock_extent(birds);
  EXPECT_EQ(e.finite, 3u);
  EXPECT_EQ(e.centre, glm::dvec3(200, 0, 0));
  EXPECT_EQ(e.mean_velocity, glm::dvec3(20, 0, 0));
  EXPECT_DOUBLE_EQ(e.radius, 100.0);
  EXPECT_DOUBLE_EQ(e.rms_radius, std::sqrt(2.0 * 100.0 * 100.0 / 3.0));
  EXPECT_TRUE(is_finite(birds[0]));
  EXPECT_FALSE(is_finite(birds[3]));
}

RunSummary sample_summary() {
  RunSummary r;
  r.backend = "cpu";
  r.device = "cpu reference (1 threads, test)";
  r.scenario = "test";
  r.steps = 1000;
  r.dt = 0.0003;
  r.steps_per_frame = 100;
  r.sim_seconds = 0.3;
  r.wall_seconds = 2.0;
  r.stats = flock_statistics({bird({0, 100, 0}, {1000, 0, 0}), bird({0, 300, 0}, {0, 0, 0})}, {});
  return r;
}

TEST(Summary, JsonHasEveryKey) {
  const nlohmann::ordered_json j = summary_json(sample_summary());
  for (const char* key : {"backend",
                          "device",
                          "scenario",
                          "birds",
                          "steps",
                          "dt",
                          "steps_per_frame",
                          "sim_seconds",
                          "wall_seconds",
                          "bird_steps_per_second",
                          "nan_birds",
                          "centroid",
                          "mean_speed",
                          "targets_reached",
                          "perched",
                          "landed",
                          "flying",
                          "flocking",
                          "quarantined",
                          "signal",
                          "error",
                          "vtk_queue",
                          "wind_beyond_airspeed",
                          "structure"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["signal"].is_null());
  EXPECT_TRUE(j["error"].is_null());
  EXPECT_TRUE(j["vtk_queue"].is_null());  // no --vtk
  RunSummary stopped = sample_summary();
  stopped.signal = "SIGTERM";
  stopped.error = "cannot write out/vtk/flock.pvd: No space left on device";
  stopped.vtk_queue_frames = 3;
  stopped.vtk_queue_bytes = 1200;
  stopped.vtk_queue_bound = 4;
  const nlohmann::ordered_json s = summary_json(stopped);
  EXPECT_EQ(s["signal"], "SIGTERM");
  EXPECT_EQ(s["error"], stopped.error);
  EXPECT_EQ(s["vtk_queue"],
            (nlohmann::ordered_json{
                {"high_water_frames", 3}, {"high_water_bytes", 1200}, {"bound_frames", 4}}));
  EXPECT_EQ(j["birds"], 2);
  EXPECT_DOUBLE_EQ(j["bird_steps_per_second"].get<double>(), 1000.0);  // 2 birds x 1000 / 2 s
  EXPECT_EQ(j["centroid"], nlohmann::json::array({0.0, 200.0, 0.0}));
  EXPECT_DOUBLE_EQ(j["mean_speed"].get<double>(), 500.0);
}

// --structure-from (issue 41): each flock's figures, the mean of its snapshots, with their units.
TEST(Summary, TheFlocksStructureIsTheMeanOfItsSnapshots) {
  RunSummary r = sample_summary();
  EXPECT_TRUE(summary_json(r)["structure"].empty());
  FlockStructureSummary f{"murmuration", "starling", 100.0, 10.0, 20.0, 1.0, {}, {}};
  StructureFigures a, b;
  a.median_nearest = 200.0, b.median_nearest = 300.0;
  a.thinnest_from_vertical = radians(10.0), b.thinnest_from_vertical = radians(20.0);
  a.anisotropy[0] = 0.6, b.anisotropy[0] = 0.4;
  a.motion_on_axes = {0.0, 1.0, 0.0}, b.motion_on_axes = {0.0, 0.0, 1.0};
  f.structure.add(a, 10.02);
  f.structure.add(b, 11.01);
  r.structure = {f};
  const nlohmann::ordered_json s = summary_json(r)["structure"][0];
  EXPECT_EQ(s["flock"], "murmuration");
  EXPECT_EQ(s["samples"], 2);
  EXPECT_DOUBLE_EQ(s["first"].get<double>(), 10.02);
  EXPECT_DOUBLE_EQ(s["last"].get<double>(), 11.01);
  EXPECT_DOUBLE_EQ(s["every"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(s["median_nearest"].get<double>(), 250.0);
  EXPECT_NEAR(s["thinnest_from_vertical"].get<double>(), 15.0, 1e-12);  // degrees
  EXPECT_DOUBLE_EQ(s["anisotropy"][0].get<double>(), 0.5);
  EXPECT_EQ(s["anisotropy"].size(), kStructureRanks);
  EXPECT_DOUBLE_EQ(s["motion_on_axes"]["width"].get<double>(), 0.5);
  EXPECT_TRUE(summary_json(r)["units"].contains("structure.anisotropy"));
}

// A wind across a leg at least as fast as its flock flies through the air (issue 39), or against
// it faster than the birds make way, is reported, leg by leg, where it blows so; slower, or with
// the flight however strong, it is not.
TEST(Summary, ALegTheWindBlowsAcrossFasterThanItsBirdsFlyIsReported) {
  Scenario s = load_scenario("migration");  // 100 km east, 300-600 m up, a power law from 10 m
  const double cruise = s.species[s.flocks[0].species].cruise_speed;
  s.world.wind_height = 45000.0;  // the wind below at 450 m, the first target's height
  s.world.wind = glm::dvec3{0.0, 0.0, 0.8 * cruise};
  EXPECT_TRUE(wind_warnings(s).empty());
  s.world.wind = glm::dvec3{3.0 * cruise, 0.0, 0.0};  // along every leg
  EXPECT_TRUE(wind_warnings(s).empty());
  s.world.wind = glm::dvec3{3.0 * cruise, 0.0, 1.2 * cruise};
  const std::vector<WindWarning> w = wind_warnings(s);
  ASSERT_EQ(w.size(), 4u);  // to each of the four targets
  EXPECT_EQ(w[0].flock, "migrants");
  EXPECT_EQ(w[0].target, "km-525");
  EXPECT_NEAR(w[0].across, 1.2 * cruise, 1e-9);  // at the target, 450 m: stronger than at 300 m
  EXPECT_EQ(w[0].height, 45000.0);
  EXPECT_EQ(w[0].airspeed, cruise);
  EXPECT_EQ(w[1].target, "km-550");
  EXPECT_EQ(w[1].height, 60000.0);
  EXPECT_GT(w[1].across, w[0].across);
  EXPECT_EQ(w[0].sentence(),
            "flock \"migrants\" cannot hold its leg from its spawn to \"km-525\": at 450 m the "
            "wind blows 12.0 m/s across it, and its birds fly at 10.0 m/s; they head into it and "
            "drift");
  EXPECT_TRUE(w[1].sentence().starts_with(
      "flock \"migrants\" cannot hold its leg from \"km-525\" to \"km-550\""))
      << w[1].sentence();
  RunSummary r;
  r.wind = w;
  const nlohmann::ordered_json j = summary_json(r)["wind_beyond_airspeed"];
  ASSERT_EQ(j.size(), 4u);
  EXPECT_EQ(j[0]["flock"], "migrants");
  EXPECT_TRUE(j[0]["from"].is_null());  // its spawn
  EXPECT_EQ(j[1]["from"], "km-525");
  EXPECT_EQ(j[0]["target"], "km-525");
  EXPECT_NEAR(j[0]["across_wind"].get<double>(), 1200.0, 1e-9);
  EXPECT_NEAR(j[0]["against_wind"].get<double>(), -3.0 * cruise, 1e-9);  // a tailwind
  EXPECT_EQ(j[0]["height"].get<double>(), 45000.0);
  EXPECT_EQ(j[0]["airspeed"].get<double>(), 1000.0);

  // A headwind: against the flight as fast as the birds fly at 450 m, the first leg's higher end
  // (the route is due east), and slower (at most 0.94 V at 600 m, the highest).
  s.world.wind = glm::dvec3{-0.9 * cruise, 0.0, 0.0};
  EXPECT_TRUE(wind_warnings(s).empty());
  s.world.wind = glm::dvec3{-1.0 * cruise, 0.0, 0.0};
  const std::vector<WindWarning> head = wind_warnings(s);
  ASSERT_EQ(head.size(), 4u);
  EXPECT_EQ(head[0].against, cruise);  // at 450 m, where it blows hardest
  EXPECT_EQ(head[0].across, 0.0);
  EXPECT_EQ(head[0].sentence(),
            "flock \"migrants\" cannot hold its leg from its spawn to \"km-525\": at 450 m the "
            "wind blows 0.0 m/s across it and 10.0 m/s against it, and its birds fly at 10.0 m/s; "
            "they head into it and drift");
  // A flock that does not flock: its birds fly faster against the wind, up to max_speed.
  s.flocks[0].flocking = false;
  ASSERT_GT(s.species[s.flocks[0].species].max_speed, 1.1 * cruise);
  EXPECT_TRUE(wind_warnings(s).empty());
  s.flocks[0].flocking = true;
  // Across and against together: 0.8 V across at 450 m leaves 0.6 V along the first leg.
  auto first_leg_warned = [&] {
    const std::vector<WindWarning> all = wind_warnings(s);
    return std::any_of(all.begin(), all.end(),
                       [](const WindWarning& x) { return x.from.empty() && x.target == "km-525"; });
  };
  s.world.wind = glm::dvec3{-0.59 * cruise, 0.0, 0.8 * cruise};
  EXPECT_FALSE(first_leg_warned());
  s.world.wind = glm::dvec3{-0.61 * cruise, 0.0, 0.8 * cruise};
  EXPECT_TRUE(first_leg_warned());
}

// docs/MODEL.md's flock metrics from hand-placed birds: four in a row 1 m apart and one 10 m off.
TEST(FlockMetrics, NearestNeighbourClosenessPolarisationAndClusters) {
  std::vector<BirdState> birds;
  for (int i = 0; i < 4; ++i) birds.push_back(bird({100.0 * i, 100, 0}, {1000, 0, 0}));
  birds.push_back(bird({1300.0, 100, 0}, {0, 0, 1000}));
  birds.push_back(bird({130.0, 100, 30}, {1000, 0, 0}));  // 42.4 cm from the second: too close
  const std::vector<Species> species = {starling()};      // wingspan (box_c) 100 cm
  const FlockMetrics m = flock_metrics(birds, species);
  EXPECT_EQ(m.birds, 6u);
  // Nearest: 100, 42.4, 76.2 (the third to the sixth), 100, 1000, 42.4: median (76.2 + 100) / 2.
  EXPECT_NEAR(m.median_nearest, 0.5 * (std::hypot(70.0, 30.0) + 100.0), 1e-9);
  EXPECT_NEAR(m.too_close, 2.0 / 6.0, 1e-12);
  EXPECT_NEAR(m.polarisation, std::hypot(5.0, 1.0) / 6.0, 1e-12);
  EXPECT_NEAR(m.largest_cluster, 5.0 / 6.0, 1e-12);  // the far one is 10 m from the row's end
  // Only the members asked for.
  EXPECT_EQ(flock_metrics(birds, species, {0, 1}).median_nearest, 100.0);
  EXPECT_EQ(flock_metrics({}, species).birds, 0u);
}

TEST(Summary, WritesAtomically) {
  const auto dir = std::filesystem::temp_directory_path() / "aeroflock-test-summary";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto path = dir / "summary.json";
  write_summary(path, sample_summary());
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["scenario"], "test");
  // Nothing beside it: no temporary left.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);

  const auto bad = dir / "no-such-dir" / "summary.json";
  try {
    write_summary(bad, sample_summary());
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(bad.parent_path()));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace aeroflock
