// Scenario files: the built-ins load, fields convert, and every bad input says where it is.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/scenario_file.h"
#include "io/species_fields.h"
#include "model/constants.h"
#include "model/simulation.h"

namespace aeroflock {
namespace {

// A small valid scenario; the error cases below edit it.
const std::string kValid = R"([simulation]
dt = 0.0003

[[targets]]
name = "t1"
centre = [0.0, 3000.0, 10000.0]

[[routes]]
name = "r"
targets = ["t1"]

[[flocks]]
species = "starling"
route = "r"
count = 3
centre = [0.0, 3000.0, 0.0]
)";

// The ScenarioError message `text` gives, or a test failure.
std::string error_of(const std::string& text, const std::string& name = "bad.toml") {
  try {
    parse_scenario(text, name);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ScenarioError for:\n" << text;
  return "";
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

const Species& species_named(const Scenario& s, const std::string& name) {
  for (const Species& sp : s.species)
    if (sp.name == name) return sp;
  throw std::runtime_error("no species " + name);
}

// Species is a name and then doubles only: the field table must name every one of them, once.
TEST(SpeciesFields, CoverEveryMemberOfSpecies) {
  const Species s;
  const auto* base = reinterpret_cast<const char*>(&s);
  std::vector<size_t> offsets;
  for (const io::SpeciesField& f : io::species_fields())
    offsets.push_back(static_cast<size_t>(reinterpret_cast<const char*>(&(s.*f.member)) - base));
  std::sort(offsets.begin(), offsets.end());
  for (size_t i = 0; i < offsets.size(); ++i)
    EXPECT_EQ(offsets[i], sizeof(std::string) + i * sizeof(double)) << "field " << i;
  EXPECT_EQ(sizeof(Species), sizeof(std::string) + offsets.size() * sizeof(double))
      << "a Species member is missing from engine/io/species_fields.cpp";
}

TEST(BuiltinScenarios, AllLoadAndValidate) {
  const std::vector<BuiltinScenario> builtins = builtin_scenarios();
  ASSERT_GE(builtins.size(), 10u);
  for (const BuiltinScenario& b : builtins) {
    SCOPED_TRACE(b.name);
    EXPECT_FALSE(b.description.empty());
    Scenario s;
    ASSERT_NO_THROW(s = load_scenario(b.name));
    EXPECT_EQ(s.name, b.name);
    EXPECT_NO_THROW(validate(s));
    EXPECT_FALSE(s.flocks.empty());
    EXPECT_EQ(s.world.target_now.size(), s.world.targets.size());
  }
}

TEST(BuiltinScenarios, TheFiguresAreThere) {
  for (const char* name :
       {"default", "fig16-circling-eagle", "fig16-fixed-rate", "fig17-ground-effect",
        "fig17-no-ground-effect", "fig18-branch-path-control", "fig18-branch-direct",
        "fig19-takeoff-no-legs", "fig20-takeoff-legs", "fig21-moving-target"})
    EXPECT_NO_THROW(load_scenario(name)) << name;
  EXPECT_EQ(load_scenario("fig16-fixed-rate").world.turning, TurningModel::fixed_rate);
  EXPECT_EQ(load_scenario("fig16-circling-eagle").world.turning, TurningModel::tail);
  EXPECT_FALSE(load_scenario("fig17-no-ground-effect").world.ground_effect);
  const Scenario fig19 = load_scenario("fig19-takeoff-no-legs");
  EXPECT_EQ(fig19.species[fig19.flocks[0].species].leg_force, 0.0);
  EXPECT_TRUE(fig19.flocks[0].standing);
}

TEST(BuiltinScenarios, UnknownNameIsAnError) {
  EXPECT_THROW(load_scenario("no-such-scenario"), ScenarioError);
}

TEST(ScenarioFile, ReadsValuesInFileUnits) {
  const Scenario s = parse_scenario(R"(
[simulation]
description = "d"
dt = 0.0005
steps_per_frame = 50
duration = 3
seed = 7
turning = "fixed-rate"
wind = [1.0, 2.0, 3.0]
[ground]
height = 1.0
effect = false
[[targets]]
name = "t"
centre = [1.0, 2.0, 3.0]
velocity = [0.0, 0.0, 500.0]
[[branches]]
name = "oak"
point = [0.0, 500.0, 0.0]
direction = [3.0, 0.0, 4.0]
[[routes]]
name = "r"
targets = ["t"]
branch = "oak"
path_control = false
[[flocks]]
name = "f"
species = "eagle"
route = "r"
heading = 90.0
standing = true
)",
                                    "dir/my-run.toml");
  EXPECT_EQ(s.name, "my-run");
  EXPECT_EQ(s.description, "d");
  EXPECT_DOUBLE_EQ(s.dt, 0.0005);
  EXPECT_EQ(s.steps_per_frame, 50u);
  EXPECT_DOUBLE_EQ(s.duration, 3.0);
  EXPECT_EQ(s.seed, 7u);
  EXPECT_EQ(s.world.turning, TurningModel::fixed_rate);
  EXPECT_EQ(s.world.wind, glm::dvec3(1, 2, 3));
  EXPECT_DOUBLE_EQ(s.world.ground_height, 1.0);
  EXPECT_FALSE(s.world.ground_effect);
  ASSERT_EQ(s.world.target_now.size(), 1u);
  EXPECT_EQ(s.world.target_now[0], glm::dvec3(1, 2, 3));
  EXPECT_EQ(s.world.targets[0].velocity, glm::dvec3(0, 0, 500));
  EXPECT_DOUBLE_EQ(s.world.branches[0].direction.x, 0.6);
  EXPECT_DOUBLE_EQ(s.world.branches[0].direction.z, 0.8);
  const Route& r = s.world.routes[0];
  EXPECT_EQ(r.targets, std::vector<uint32_t>{0});
  EXPECT_EQ(r.branch, 0);
  EXPECT_FALSE(r.loop);
  EXPECT_FALSE(r.path_control);
  const Flock& f = s.flocks[0];
  EXPECT_EQ(s.species[f.species].name, "eagle");
  EXPECT_DOUBLE_EQ(f.heading, kPi / 2);
  EXPECT_TRUE(f.standing);
  EXPECT_EQ(f.count, 1u);
}

TEST(ScenarioFile, SpeciesInheritsFromBaseAndConvertsDegrees) {
  const Scenario s = parse_scenario(kValid + R"(
[[species]]
name = "big-starling"
base = "starling"
mass = 600.0
bend_max = 20.0
turn_rate = 90
[[species]]
name = "bigger"
base = "big-starling"
wing_area = 2000
)",
                                    "species.toml");
  const Species starling_preset = starling();
  const Species& big = species_named(s, "big-starling");
  EXPECT_DOUBLE_EQ(big.mass, 600.0);
  EXPECT_DOUBLE_EQ(big.bend_max, radians(20.0));
  EXPECT_DOUBLE_EQ(big.turn_rate, radians(90.0));
  EXPECT_DOUBLE_EQ(big.wing_area, starling_preset.wing_area);
  EXPECT_DOUBLE_EQ(big.rot_max, starling_preset.rot_max);
  EXPECT_DOUBLE_EQ(big.leg_force, starling_preset.leg_force);
  const Species& bigger = species_named(s, "bigger");
  EXPECT_DOUBLE_EQ(bigger.mass, 600.0);
  EXPECT_DOUBLE_EQ(bigger.wing_area, 2000.0);
  EXPECT_NO_THROW(species_named(s, "eagle"));  // the presets are always there
}

// Each bad input: the edit to kValid and the start of the message it must give.
struct BadCase {
  const char* what;
  std::string text;
  std::string message;
};

TEST(ScenarioFile, BadInputsSayFileLineColumnAndKey) {
  const std::string species = "\n[[species]]\nname = \"x\"\nbase = \"starling\"\n";
  const BadCase cases[] = {
      {"syntax error", replace(kValid, "dt = 0.0003", "dt = 0.0003 0.1"),
       "bad.toml:2:13: error: syntax error while parsing key-value pair"},
      {"unknown key", replace(kValid, "count = 3", "cuont = 3"),
       "bad.toml:15:1: error: flocks[0].cuont: unknown key (did you mean 'count'?); valid keys: "
       "name, "
       "species, route"},
      {"unknown table", replace(kValid, "[simulation]", "[simulaton]"),
       "bad.toml:1:2: error: simulaton: unknown key (did you mean 'simulation'?); valid keys: "
       "simulation, ground"},
      {"wrong type", replace(kValid, "count = 3", "count = \"many\""),
       "bad.toml:15:9: error: flocks[0].count: expected a positive integer, got \"many\""},
      {"wrong type vec3", replace(kValid, "centre = [0.0, 3000.0, 10000.0]", "centre = 1"),
       "bad.toml:6:10: error: targets[0].centre: expected an array of 3 numbers, got 1"},
      {"dt <= 0", replace(kValid, "dt = 0.0003", "dt = 0.0"),
       "bad.toml:2:6: error: simulation.dt: expected a number from 1e-05 to 0.01, got 0"},
      {"fidelity unknown", replace(kValid, "dt = 0.0003", "fidelity = \"quick\""),
       "bad.toml:2:12: error: simulation.fidelity: expected \"paper\" or \"fast\", got \"quick\""},
      {"fidelity and dt", replace(kValid, "dt = 0.0003", "dt = 0.0003\nfidelity = \"fast\""),
       "bad.toml:3:12: error: simulation.fidelity: dt is given too: give the step in one place"},
      {"a wait past 2^32 steps",
       replace(kValid, "dt = 0.0003", "dt = 0.0001") + "standing = true\ntakeoff_time = 500000.0\n",
       "bad.toml:18:16: error: flocks[0].takeoff_time: more than 2^32 - 1 steps of dt (0.000100 "
       "s): the wait is counted in whole steps"},
      {"count 0", replace(kValid, "count = 3", "count = 0"),
       "bad.toml:15:9: error: flocks[0].count: expected a positive integer, got 0"},
      {"count negative", replace(kValid, "count = 3", "count = -3"),
       "bad.toml:15:9: error: flocks[0].count: expected a positive integer, got -3"},
      {"f_min > f_max", kValid + species + "f_min = 12.0\n",
       "bad.toml:21:9: error: species[0].f_min: species 'x': f_min must be <= f_max, got 12"},
      {"separation zone shorter ahead", kValid + species + "separation_front = 0.5\n",
       "bad.toml:21:20: error: species[0].separation_front: species 'x': separation_front must be "
       ">= 1, got 0.5"},
      {"perches neither 0 nor 1", kValid + species + "perches = 0.5\n",
       "bad.toml:21:11: error: species[0].perches: species 'x': perches must be 0 (ground) or 1 "
       "(branches), got 0.5"},
      {"separation all round neither 0 nor 1", kValid + species + "separation_all_round = 0.5\n",
       "bad.toml:21:24: error: species[0].separation_all_round: species 'x': separation_all_round "
       "must be 0 (its k nearest from those it sees) or 1 (all round), got 0.5"},
      {"negative mass", kValid + species + "mass = -5.0\n",
       "bad.toml:21:8: error: species[0].mass: species 'x': mass must be > 0, got -5"},
      {"unknown route", replace(kValid, "route = \"r\"", "route = \"q\""),
       "bad.toml:14:9: error: flocks[0].route: unknown route \"q\" (known: r)"},
      {"unknown species", replace(kValid, "species = \"starling\"", "species = \"crow\""),
       "bad.toml:13:11: error: flocks[0].species: unknown species \"crow\""},
      {"unknown target", replace(kValid, "targets = [\"t1\"]", "targets = [\"t1\", \"t2\"]"),
       "bad.toml:10:18: error: routes[0].targets[1]: unknown target \"t2\" (known: t1)"},
      {"route without targets", replace(kValid, "targets = [\"t1\"]", "targets = []"),
       "bad.toml:10:11: error: routes[0].targets: expected at least one target name"},
      {"duplicate name", kValid + "[[targets]]\nname = \"t1\"\ncentre = [0, 0, 0]\n",
       "bad.toml:18:8: error: targets[1].name: duplicate target name \"t1\""},
      {"missing key", replace(kValid, "route = \"r\"", ""),
       "bad.toml:12:1: error: flocks[0].route: missing required key"},
      {"radius <= 0", replace(kValid, "name = \"t1\"", "name = \"t1\"\nradius = -1"),
       "bad.toml:6:10: error: targets[0].radius: expected a positive number, got -1"},
      {"steps_per_frame", replace(kValid, "dt = 0.0003", "steps_per_frame = 0"),
       "bad.toml:2:19: error: simulation.steps_per_frame: expected a positive integer, got 0"},
      {"loop over one target",
       replace(kValid, "targets = [\"t1\"]", "targets = [\"t1\"]\nloop = true"),
       "bad.toml:11:8: error: routes[0].loop: a looping route needs at least two targets"},
      {"perch beyond braking", kValid + species + "perch_radius = 900.0\n",
       "bad.toml:21:16: error: species[0].perch_radius: species 'x': perch_radius must be <= "
       "brake_distance"},
      {"turning", replace(kValid, "dt = 0.0003", "turning = \"left\""),
       "bad.toml:2:11: error: simulation.turning: expected \"tail\" or \"fixed-rate\""},
      {"length unit", "[units]\nlength = \"furlong\"\n" + kValid,
       "bad.toml:2:10: error: units.length: expected \"mm\", \"cm\", \"m\" or \"km\", got "
       "\"furlong\""},
      {"length unit type", "[units]\nlength = 100\n" + kValid,
       "bad.toml:2:10: error: units.length: expected a string"},
      {"wind profile", kValid + "[wind]\nprofile = \"cubic\"\n",
       "bad.toml:18:11: error: wind.profile: expected \"uniform\", \"power-law\" or "
       "\"logarithmic\", got \"cubic\""},
      {"wind exponent", kValid + "[wind]\nexponent = 1.5\n",
       "bad.toml:18:12: error: wind.exponent: expected a number from 0 to 1, got 1.5"},
      {"wind roughness", kValid + "[wind]\nheight = 500.0\nroughness = 600.0\n",
       "bad.toml:19:13: error: wind.roughness: the roughness length must be below the reference "
       "height"},
      {"wind twice",
       replace(kValid, "dt = 0.0003", "wind = [100.0, 0.0, 0.0]") +
           "[wind]\nvelocity = [1.0, 0.0, 0.0]\n",
       "bad.toml:2:8: error: simulation.wind: the wind is set in [wind] too"},
      {"beyond 20,000 km",
       replace(kValid, "centre = [0.0, 3000.0, 10000.0]", "centre = [3.0e9, 3000.0, 0.0]"),
       "bad.toml:6:11: error: targets[0].centre[0]: expected at most 2e+09 (the world's radius, "
       "20,000 km), got 3e+09"},
      {"wake without flocking", kValid + "wake = true\n",
       "bad.toml:17:8: error: flocks[0].wake: a bird meets the wakes of the birds it sees: wake = "
       "true needs flocking = true"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string message = error_of(c.text);
    EXPECT_EQ(message.substr(0, c.message.size()), c.message) << message;
  }
}

TEST(ScenarioFile, LengthsInTheFilesUnit) {
  // Every length and speed of the world in the [units] length; species keep theirs.
  const std::string world = R"(
[simulation]
wind = [0.2, 0.0, -0.1]

[ground]
height = -12.5

[[targets]]
name = "t1"
centre = [500.0, 0.3, -2.0]
radius = 0.05
velocity = [0.001, 0.0, 0.0]
amplitude = [0.0, 0.01, 0.0]
period = 4.0

[[branches]]
name = "b"
point = [1.0, 0.002, 0.0]
length = 0.0015

[[routes]]
name = "r"
targets = ["t1"]

[[flocks]]
species = "starling"
route = "r"
centre = [499.0, 0.3, 0.0]
extent = [0.01, 0.002, 0.01]
speed = 0.012

[[species]]
name = "s"
base = "starling"
perception_radius = 1500.0
)";
  for (const auto& [unit, cm] : {std::pair{"mm", 0.1}, {"cm", 1.0}, {"m", 100.0}, {"km", 1.0e5}}) {
    SCOPED_TRACE(unit);
    const Scenario s =
        parse_scenario("[units]\nlength = \"" + std::string(unit) + "\"\n" + world, "u.toml");
    const World& w = s.world;
    EXPECT_DOUBLE_EQ(w.wind.x, 0.2 * cm);
    EXPECT_DOUBLE_EQ(w.wind.z, -0.1 * cm);
    EXPECT_DOUBLE_EQ(w.ground_height, -12.5 * cm);
    EXPECT_DOUBLE_EQ(w.targets[0].centre.x, 500.0 * cm);
    EXPECT_DOUBLE_EQ(w.targets[0].centre.y, 0.3 * cm);
    EXPECT_DOUBLE_EQ(w.targets[0].radius, 0.05 * cm);
    EXPECT_DOUBLE_EQ(w.targets[0].velocity.x, 0.001 * cm);
    EXPECT_DOUBLE_EQ(w.targets[0].amplitude.y, 0.01 * cm);
    EXPECT_DOUBLE_EQ(w.targets[0].period, 4.0);  // seconds stay seconds
    EXPECT_DOUBLE_EQ(w.branches[0].point.y, 0.002 * cm);
    EXPECT_DOUBLE_EQ(w.branches[0].length, 0.0015 * cm);
    EXPECT_DOUBLE_EQ(s.flocks[0].spawn_centre.x, 499.0 * cm);
    EXPECT_DOUBLE_EQ(s.flocks[0].spawn_extent.y, 0.002 * cm);
    EXPECT_DOUBLE_EQ(s.flocks[0].speed, 0.012 * cm);
    EXPECT_DOUBLE_EQ(species_named(s, "s").perception_radius, 1500.0);  // species.def's cm
  }
  // Without [units]: cm.
  EXPECT_DOUBLE_EQ(parse_scenario(world, "u.toml").world.targets[0].centre.x, 500.0);
}

// Issue 13: `fidelity` names the step and keeps a frame 30 ms of flight; steps_per_frame may
// still say otherwise.
TEST(ScenarioFile, FidelityNamesTheStep) {
  const Scenario fast =
      parse_scenario(replace(kValid, "dt = 0.0003", "fidelity = \"fast\""), "f.toml");
  EXPECT_EQ(fast.dt, kFastDt);
  EXPECT_EQ(fast.steps_per_frame, 15u);
  EXPECT_STREQ(fidelity_name(fast.dt), "fast");
  const Scenario paper =
      parse_scenario(replace(kValid, "dt = 0.0003", "fidelity = \"paper\""), "p.toml");
  EXPECT_EQ(paper.dt, kPaperDt);
  EXPECT_EQ(paper.steps_per_frame, 100u);
  const Scenario own = parse_scenario(
      replace(kValid, "dt = 0.0003", "fidelity = \"fast\"\nsteps_per_frame = 5"), "o.toml");
  EXPECT_EQ(own.steps_per_frame, 5u);
  // set_dt keeps the frame's length.
  Scenario s = paper;
  set_dt(s, 0.001);
  EXPECT_EQ(s.steps_per_frame, 30u);
  EXPECT_STREQ(fidelity_name(s.dt), "custom");
  EXPECT_EQ(load_scenario("murmuration").dt, kFastDt);
  EXPECT_EQ(load_scenario("fig16-circling-eagle").dt, kPaperDt);
}

TEST(ScenarioFile, WindProfile) {
  const Scenario s = parse_scenario(kValid + R"(
[units]
length = "m"

[wind]
velocity = [3.0, 0.0, 4.0]
profile = "logarithmic"
height = 10.0
roughness = 0.03
)",
                                    "w.toml");
  EXPECT_EQ(s.world.wind_profile, WindProfile::logarithmic);
  EXPECT_DOUBLE_EQ(s.world.wind.z, 400.0);
  EXPECT_DOUBLE_EQ(s.world.wind_height, 1000.0);
  EXPECT_DOUBLE_EQ(s.world.wind_roughness, 3.0);
  const Scenario p =
      parse_scenario(kValid + "[wind]\nprofile = \"power-law\"\nexponent = 0.2\n", "w.toml");
  EXPECT_EQ(p.world.wind_profile, WindProfile::power_law);
  EXPECT_DOUBLE_EQ(p.world.wind_exponent, 0.2);
  EXPECT_DOUBLE_EQ(p.world.wind_height, 1000.0);  // the default reference: 10 m
}

TEST(ScenarioFile, ErrorsNameTheFileTheyCameFrom) {
  const auto dir = std::filesystem::temp_directory_path() / "aeroflock-test-scenario-file";
  std::filesystem::create_directories(dir);
  const auto path = dir / "bad-count.toml";
  std::ofstream(path) << replace(kValid, "count = 3", "count = -3");
  try {
    read_scenario_file(path);
    ADD_FAILURE() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()),
              path.string() + ":15:9: error: flocks[0].count: expected a positive integer, got -3");
  }
  std::filesystem::remove_all(dir);
}

TEST(ScenarioFile, MissingFileIsAScenarioError) {
  try {
    read_scenario_file("/no/such/dir/missing.toml");
    ADD_FAILURE() << "no error";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/no/such/dir/missing.toml: error: cannot read the scenario file: "
              "No such file or directory");
  }
  EXPECT_THROW(load_scenario("/no/such/dir/missing.toml"), ScenarioError);
}

// Issue 16: every number a file gives is finite, normal in the device's float and within its
// physical range (species.def's max, scenario.h's ranges), said at its line and column. Each of
// these ran on main, to 0 steps, NaN birds or no end.
TEST(ScenarioLimits, NumbersOutsideTheirRangeSayWhere) {
  const std::string species = "\n[[species]]\nname = \"x\"\nbase = \"starling\"\n";
  const std::string subnormal =
      "expected 0 or a number at least 1.1754944e-38 in size (a smaller one is subnormal in the "
      "device's float), got ";
  const BadCase cases[] = {
      {"dt 2 s (NaN birds)", replace(kValid, "dt = 0.0003", "dt = 2.0"),
       "bad.toml:2:6: error: simulation.dt: expected at most 0.01 (the convergence study's range, "
       "docs/convergence.md), got 2"},
      {"dt 1e-9 (no end)", replace(kValid, "dt = 0.0003", "dt = 1e-9"),
       "bad.toml:2:6: error: simulation.dt: expected a number from 1e-05 to 0.01, got 1e-09"},
      {"dt 1e-45 (0 steps)", replace(kValid, "dt = 0.0003", "dt = 1e-45"),
       "bad.toml:2:6: error: simulation.dt: expected a number from 1e-05 to 0.01, got 1e-45"},
      {"dt nan", replace(kValid, "dt = 0.0003", "dt = nan"),
       "bad.toml:2:6: error: simulation.dt: expected a finite number, got nan"},
      {"dt inf", replace(kValid, "dt = 0.0003", "dt = -inf"),
       "bad.toml:2:6: error: simulation.dt: expected a finite number, got -inf"},
      {"steps_per_frame 1e9", replace(kValid, "dt = 0.0003", "steps_per_frame = 1000000000"),
       "bad.toml:2:19: error: simulation.steps_per_frame: expected an integer <= 100000, got "
       "1000000000"},
      {"duration 1e19", replace(kValid, "dt = 0.0003", "duration = 1e19"),
       "bad.toml:2:12: error: simulation.duration: expected at most 1e+06 (11.6 days), got 1e+19"},
      {"flock speed 1e20", replace(kValid, "count = 3", "count = 3\nspeed = 1e20"),
       "bad.toml:16:9: error: flocks[0].speed: expected at most 34300 (the speed of sound), got "
       "1e+20"},
      {"wind 1e308", replace(kValid, "dt = 0.0003", "wind = [1e308, 0.0, 0.0]"),
       "bad.toml:2:9: error: simulation.wind[0]: expected at most 34300 (the speed of sound), got "
       "1e+308"},
      {"wind in m/s",
       "[units]\nlength = \"m\"\n" + kValid + "[wind]\nvelocity = [0.0, 0.0, 400.0]\n",
       "bad.toml:20:23: error: wind.velocity[2]: expected at most 343 (the speed of sound), got "
       "400"},
      {"target period 5e-324", replace(kValid, "name = \"t1\"", "name = \"t1\"\nperiod = 5e-324"),
       "bad.toml:6:10: error: targets[0].period: expected 0 or a number from 0.1 to 1e+06, got "
       "5e-324"},
      {"target radius subnormal", replace(kValid, "name = \"t1\"", "name = \"t1\"\nradius = 1e-40"),
       "bad.toml:6:10: error: targets[0].radius: expected a number at least 1.1754944e-38 in size "
       "(a smaller one is subnormal in the device's float), got 1e-40"},
      {"species subnormal", kValid + species + "shoulder_x = -1e-310\n",
       "bad.toml:21:14: error: species[0].shoulder_x: " + subnormal + "-1e-310"},
      {"target period 1 ms", replace(kValid, "name = \"t1\"", "name = \"t1\"\nperiod = 0.001"),
       "bad.toml:6:10: error: targets[0].period: expected 0 or a number from 0.1 to 1e+06, got "
       "0.001"},
      {"target velocity",
       replace(kValid, "name = \"t1\"", "name = \"t1\"\nvelocity = [0, -1e300, 0]"),
       "bad.toml:6:16: error: targets[0].velocity[1]: expected a number from -34300 to 34300, got "
       "-1e+300"},
      {"ground 1e308", kValid + "[ground]\nheight = -1e308\n",
       "bad.toml:18:10: error: ground.height: expected a number from -2e+09 to 2e+09, got -1e+308"},
      {"heading", replace(kValid, "count = 3", "count = 3\nheading = 1e308"),
       "bad.toml:16:11: error: flocks[0].heading: expected at most 360 (a turn), got 1e+308"},
      {"species mass 1e308", kValid + species + "mass = 1e308\n",
       "bad.toml:21:8: error: species[0].mass: species 'x': mass must be <= 1e+06, got 1e+308"},
      {"species wingbeat angle", kValid + species + "A_arm = -1e308\n",
       "bad.toml:21:9: error: species[0].A_arm: species 'x': A_arm must be within +-180 degrees, "
       "got -1e+308"},
      {"species rate", kValid + species + "roll_rate = 1e6\n",
       "bad.toml:21:13: error: species[0].roll_rate: species 'x': roll_rate must be <= 100000 "
       "deg/s, got 1e+06"},
      {"species nan", kValid + species + "f_max = nan\n",
       "bad.toml:21:9: error: species[0].f_max: expected a finite number, got nan"},
      // Row 6: passed the parser's check on main, then failed validate() with no line or column.
      {"branch direction subnormal",
       kValid + "[[branches]]\nname = \"b\"\npoint = [0.0, 500.0, 0.0]\ndirection = [1e-320, 0.0, "
                "1e-320]\n",
       "bad.toml:20:14: error: branches[0].direction[0]: " + subnormal + "1e-320"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string message = error_of(c.text);
    EXPECT_EQ(message.substr(0, c.message.size()), c.message) << message;
  }
  // The bounds themselves are legal.
  EXPECT_NO_THROW(parse_scenario(
      replace(kValid, "dt = 0.0003", "dt = 0.01\nsteps_per_frame = 100000\nduration = 1e6"),
      "ok.toml"));
  EXPECT_NO_THROW(parse_scenario(replace(kValid, "dt = 0.0003", "dt = 1e-5"), "ok.toml"));
  EXPECT_NO_THROW(
      parse_scenario(replace(kValid, "name = \"t1\"", "name = \"t1\"\nperiod = 0"), "ok.toml"));
}

// Issue 16: nothing starts under the ground, said where; Fig. 17's target lies on it and the
// take-off figures stand on it.
TEST(ScenarioLimits, NothingStartsUnderTheGround) {
  const BadCase cases[] = {
      {"flock under the ground",
       replace(kValid, "centre = [0.0, 3000.0, 0.0]", "centre = [0.0, -100.0, 0.0]"),
       "bad.toml:16:10: error: flocks[0].centre: the spawn box's lowest point, centre - extent, y "
       "= -215.38 cm, "
       "must be above the ground at 0 cm"},
      {"flock at ground height",
       replace(replace(kValid, "centre = [0.0, 3000.0, 0.0]", "centre = [0.0, 0.0, 0.0]"),
               "count = 3", "count = 1"),
       "bad.toml:16:10: error: flocks[0].centre: the spawn box's lowest point, centre - extent, y "
       "= 0 cm"},
      {"flock's box into the ground",
       replace(kValid, "centre = [0.0, 3000.0, 0.0]",
               "centre = [0.0, 3000.0, 0.0]\nextent = [0.0, 3500.0, 0.0]"),
       "bad.toml:16:10: error: flocks[0].centre: the spawn box's lowest point, centre - extent, y "
       "= -500 cm"},
      {"many birds without a box",
       replace(kValid, "centre = [0.0, 3000.0, 0.0]", "centre = [0.0, 100.0, 0.0]"),
       "bad.toml:16:10: error: flocks[0].centre: the spawn box's lowest point, centre - extent, y "
       "= -15.38 cm"},
      {"raised ground, in m", "[units]\nlength = \"m\"\n" + kValid + "[ground]\nheight = 5000.0\n",
       "bad.toml:8:10: error: targets[0].centre: a target's centre, y = 3000 m, must be on or "
       "above the ground at 5000 m"},
      {"target under the ground",
       replace(kValid, "centre = [0.0, 3000.0, 10000.0]", "centre = [0.0, -1.0, 10000.0]"),
       "bad.toml:6:10: error: targets[0].centre: a target's centre, y = -1 cm, must be on or above "
       "the ground at 0 cm"},
      {"branch under the ground",
       kValid + "[[branches]]\nname = \"b\"\npoint = [0.0, -500.0, 0.0]\n",
       "bad.toml:19:9: error: branches[0].point: a branch's point, y = -500 cm, must be on or "
       "above "
       "the ground at 0 cm"},
      {"standing at stand_height 0",
       kValid + "[[species]]\nname = \"legless\"\nbase = \"starling\"\nstand_height = 0.0\n" +
           "[[flocks]]\nspecies = \"legless\"\nroute = \"r\"\nstanding = true\n",
       "bad.toml:24:12: error: flocks[1].standing: species 'legless' has stand_height 0: its birds "
       "would stand in the ground"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.what);
    const std::string message = error_of(c.text);
    EXPECT_EQ(message.substr(0, c.message.size()), c.message) << message;
  }
  // A target on the ground (Fig. 17), a branch on it (a landing site on the ground), a standing
  // flock whose centre is on it (its birds stand at stand_height), a box just clear of it.
  EXPECT_NO_THROW(
      parse_scenario(kValid + "[[branches]]\nname = \"b\"\npoint = [0.0, 0.0, 0.0]\n", "ok.toml"));
  EXPECT_NO_THROW(parse_scenario(
      replace(kValid, "centre = [0.0, 3000.0, 10000.0]", "centre = [0.0, 0.0, 10000.0]"),
      "ok.toml"));
  EXPECT_NO_THROW(parse_scenario(
      replace(kValid, "centre = [0.0, 3000.0, 0.0]", "centre = [0.0, 0.0, 0.0]\nstanding = true"),
      "ok.toml"));
  EXPECT_NO_THROW(
      parse_scenario(replace(kValid, "centre = [0.0, 3000.0, 0.0]",
                             "centre = [0.0, 3000.0, 0.0]\nextent = [0.0, 2999.0, 0.0]"),
                     "ok.toml"));
  for (const char* name : {"fig17-ground-effect", "fig19-takeoff-no-legs", "fig20-takeoff-legs"})
    EXPECT_NO_THROW(load_scenario(name)) << name;
}

// Issue 16: the model's own checks, for scenarios made in code (the envelope's): the step, the
// frame, the duration, the ground; set_dt keeps the step's range and the frame's steps.
TEST(ScenarioLimits, ValidateAndSetDt) {
  const Scenario ok = parse_scenario(kValid, "ok.toml");
  auto complaint = [](const Scenario& s) -> std::string {
    try {
      validate(s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  Scenario s = ok;
  s.dt = 2.0;
  EXPECT_EQ(complaint(s), "dt must be within [1e-05, 0.01] s (docs/convergence.md), got 2 s");
  s = ok;
  s.steps_per_frame = 1000000000;
  EXPECT_EQ(complaint(s), "steps_per_frame must be within [1, 100000]");
  s = ok;
  s.duration = 1e19;
  EXPECT_EQ(complaint(s), "duration must be within (0, 1e+06] s");
  s = ok;
  s.world.ground_height = 5000.0;
  EXPECT_EQ(complaint(s), "target 't1' is not above the ground (y 3000 cm, the ground 5000 cm)");
  s = ok;
  s.flocks[0].spawn_centre.y = 10.0;  // three birds, a box of 2 wing lengths cbrt(3) a side
  EXPECT_EQ(complaint(s),
            "flock 'flock0': the lowest point of its spawn box is not above the ground (y -105.38 "
            "cm, the ground 0 cm)");

  s = ok;
  EXPECT_THROW(set_dt(s, 2.0), std::invalid_argument);
  EXPECT_THROW(set_dt(s, 1e-45), std::invalid_argument);
  EXPECT_EQ(s.dt, ok.dt);
  s.dt = kMaxDt;
  s.steps_per_frame = kMaxStepsPerFrame;  // frames of 1,000 s: at 10 us, 10^8 steps each
  EXPECT_THROW(set_dt(s, kMinDt), std::invalid_argument);
  EXPECT_EQ(s.steps_per_frame, kMaxStepsPerFrame);
  EXPECT_EQ(steps_in(1e30, kMinDt), UINT32_MAX);  // clamped, not a double past uint32_t cast

  // Issue 39: a standing flock's rest is counted in 32-bit steps at any dt it is given, and
  // spawning refuses one that no check saw rather than shorten it.
  const std::string late =
      "flocks[0].takeoff_time of 50000 s is more than 2^32 - 1 steps of 1e-05 s";
  s = ok;
  s.flocks[0].standing = true;
  s.flocks[0].takeoff_time = 50000.0;
  EXPECT_EQ(complaint(s), "");  // 1.7e8 steps of 0.3 ms
  EXPECT_THROW(set_dt(s, kMinDt), std::invalid_argument);
  EXPECT_EQ(s.dt, ok.dt);
  s.dt = kMinDt;
  EXPECT_EQ(complaint(s), late);
  try {
    spawn_birds(s);
    ADD_FAILURE() << "spawned birds whose rest does not fit its count";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), late);
  }
  s.flocks[0].standing = false;  // a flying flock's takeoff_time is not read
  EXPECT_EQ(complaint(s), "");
}

// Issue 16 (d): a scenario file is a regular file of at most 16 MiB; neither /dev/zero nor a
// larger file is read without end.
TEST(ScenarioLimits, FilesAreRegularAndBounded) {
  auto error_reading = [](const std::filesystem::path& path) -> std::string {
    try {
      read_scenario_file(path);
    } catch (const ScenarioError& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error for " << path;
    return "";
  };
  EXPECT_EQ(error_reading("/dev/zero"),
            "/dev/zero: error: cannot read the scenario file: it is not a regular file (a device, "
            "a pipe or a socket)");
  const auto dir = std::filesystem::temp_directory_path() / "aeroflock-test-scenario-limits";
  std::filesystem::create_directories(dir);
  EXPECT_EQ(error_reading(dir),
            dir.string() + ": error: cannot read the scenario file: it is a directory");
  const auto big = dir / "big.toml";
  {
    std::ofstream out(big);
    out << kValid << std::string(kMaxScenarioBytes, '#') << "\n";  // one long comment
  }
  EXPECT_EQ(error_reading(big),
            big.string() + ": error: cannot read the scenario file: it is " +
                std::to_string(kValid.size() + kMaxScenarioBytes + 1) +
                " bytes, more than the 16777216 bytes (16 MiB) a scenario file may be");
  std::filesystem::remove_all(dir);
  // From a buffer too (the fuzzer's way in).
  EXPECT_EQ(error_of(kValid + std::string(kMaxScenarioBytes, '#')),
            "bad.toml: error: the scenario is larger than 16777216 bytes (16 MiB), the most a "
            "scenario may be");
}

// Issue 16 (c): 10^5 targets on one route load, every name looked up once by hash (main's
// look-ups went through the list: 3e4 targets took 10.8 s). An unknown name's message names the
// first few, not all 10^5.
TEST(ScenarioLimits, HundredThousandTargetsLoad) {
  constexpr int kTargets = 100000;
  std::string text = "[simulation]\nfidelity = \"fast\"\n";
  std::string route = "[[routes]]\nname = \"r\"\ntargets = [";
  for (int i = 0; i < kTargets; ++i) {
    text += "[[targets]]\nname = \"t" + std::to_string(i) + "\"\ncentre = [" + std::to_string(i) +
            ".0, 1000.0, 0.0]\n";
    route += (i ? ", \"t" : "\"t") + std::to_string(kTargets - 1 - i) + "\"";
  }
  text +=
      route + "]\n[[flocks]]\nspecies = \"starling\"\nroute = \"r\"\ncentre = [0.0, 1000.0, 0.0]\n";
  ASSERT_LT(text.size(), kMaxScenarioBytes);
  const Scenario s = parse_scenario(text, "many.toml");
  ASSERT_EQ(s.world.targets.size(), size_t(kTargets));
  ASSERT_EQ(s.world.routes[0].targets.size(), size_t(kTargets));
  for (int i = 0; i < kTargets; ++i)
    ASSERT_EQ(s.world.routes[0].targets[i], uint32_t(kTargets - 1 - i));
  EXPECT_EQ(s.world.targets[12345].centre.x, 12345.0);
  const std::string message = error_of(
      text + "[[flocks]]\nspecies = \"starling\"\nroute = \"q\"\ncentre = [0.0, 1000.0, 0.0]\n",
      "many.toml");
  EXPECT_NE(message.find("unknown route \"q\" (known: r)"), std::string::npos) << message;
  const std::string target = error_of(replace(text, "\"t0\"]", "\"t-1\"]"), "many.toml");
  EXPECT_NE(target.find("unknown target \"t-1\" (known: t0, t1, t2,"), std::string::npos)
      << target.substr(0, 300);
  EXPECT_NE(target.find("t19 and 99980 more)"), std::string::npos) << target.substr(0, 300);
  EXPECT_LT(target.size(), 400u);
}

}  // namespace
}  // namespace aeroflock
