#include "io/scenario_file.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/species_fields.h"
#include "io/toml_reader.h"
#include "model/constants.h"

namespace aeroflock {
namespace {

using io::LocatedString;
using io::Range;
using io::TableReader;

// The physical ranges of the world's numbers (engine/model/scenario.h); a species' are in
// species.def. Lengths in cm, converted to the file's unit where read.
constexpr std::string_view kWorldWhy = "the world's radius, 20,000 km";
constexpr std::string_view kSpeedWhy = "the speed of sound";
constexpr Range kPosition = io::magnitude(kWorldRadius, kWorldWhy);
constexpr Range kLength = io::positive(kWorldRadius, kWorldWhy);
constexpr Range kVelocity = io::magnitude(kMaxSpeed, kSpeedWhy);
constexpr Range kDt =
    io::between(kMinDt, kMaxDt, "the convergence study's range, docs/convergence.md");
constexpr Range kDuration = io::positive(kMaxDuration, "11.6 days");
// Any finite number: a direction (normalised on reading), a species' field (validate() checks it
// against species.def's range, reported at the field).
constexpr Range kAnyFinite = io::magnitude(std::numeric_limits<double>::max());

using Keys = std::span<const std::string_view>;

constexpr std::string_view kTopKeys[] = {"simulation", "ground",   "units",  "wind",  "species",
                                         "targets",    "branches", "routes", "flocks"};
constexpr std::string_view kUnitsKeys[] = {"length"};
constexpr std::string_view kWindKeys[] = {"velocity", "profile", "height", "exponent", "roughness"};
constexpr std::string_view kSimulationKeys[] = {"name",     "description",     "dt",
                                                "fidelity", "steps_per_frame", "duration",
                                                "seed",     "turning",         "wind"};
constexpr std::string_view kGroundKeys[] = {"height", "effect"};
constexpr std::string_view kTargetKeys[] = {"name",     "centre",    "radius",
                                            "velocity", "amplitude", "period"};
constexpr std::string_view kBranchKeys[] = {"name", "point", "direction", "length"};
constexpr std::string_view kRouteKeys[] = {"name", "targets", "loop", "branch", "path_control"};
constexpr std::string_view kFlockKeys[] = {"name",         "species",   "route",    "count",
                                           "centre",       "extent",    "heading",  "speed",
                                           "frequency",    "amplitude", "standing", "takeoff_time",
                                           "random_phase", "flocking",  "wake"};

// "name", "base" and every Species field.
Keys species_keys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> k{"name", "base"};
    for (const io::SpeciesField& f : io::species_fields()) k.push_back(f.name);
    return k;
  }();
  return keys;
}

// The file's unit of length ([units] length): every length and speed of the world (ground,
// wind, targets, branches, flocks) is read in it; species keep their own units (species.def).
struct Lengths {
  double cm = 1.0;  // cm per unit
  std::string_view unit = "cm";

  // `range_cm` in cm: the file's numbers are checked in its unit.
  double number(const TableReader& r, std::string_view key, double fallback_cm,
                Range range_cm) const {
    return r.find(key) ? r.number(key, 0.0, in_file(range_cm)) * cm : fallback_cm;
  }
  glm::dvec3 vec3(const TableReader& r, std::string_view key, const glm::dvec3& fallback_cm,
                  Range range_cm) const {
    return r.find(key) ? r.vec3(key, glm::dvec3(0.0), in_file(range_cm)) * cm : fallback_cm;
  }
  Range in_file(Range range_cm) const {
    range_cm.min /= cm;
    range_cm.max /= cm;
    return range_cm;
  }
  // A length in cm as the file gives it: "-5 m".
  std::string text(double length_cm) const {
    std::ostringstream out;
    out << length_cm / cm << ' ' << unit;
    return out.str();
  }
};

Lengths read_units(const TableReader& top) {
  Lengths l;
  const auto units = top.table("units", kUnitsKeys);
  if (!units) return l;
  const auto length = units->located_string("length");
  if (!length) return l;
  constexpr std::pair<std::string_view, double> kKnown[] = {
      {"mm", 0.1}, {"cm", 1.0}, {"m", 100.0}, {"km", 1.0e5}};
  for (const auto& [name, cm] : kKnown)
    if (length->value == name) return {cm, name};
  io::fail(length->where,
           "expected \"mm\", \"cm\", \"m\" or \"km\", got \"" + length->value + "\"");
}

// 64-bit FNV-1a of the scenario's text, as "fnv1a64:" and 16 hex digits: enough to tell which
// scenario a file came from, not a cryptographic seal.
std::string text_hash(std::string_view text) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  char hex[32];
  std::snprintf(hex, sizeof hex, "fnv1a64:%016llx", static_cast<unsigned long long>(h));
  return hex;
}

std::string stem(std::string_view source_name) {
  return std::filesystem::path(source_name).stem().string();
}

void read_simulation(const TableReader& top, std::string_view source_name, const Lengths& L,
                     Scenario& s) {
  s.name = stem(source_name);
  const auto sim = top.table("simulation", kSimulationKeys);
  if (!sim) return;
  s.name = sim->string("name", s.name);
  s.description = sim->string("description", "");
  // The step: `dt` in seconds, or a `fidelity` that names one (docs/convergence.md); a frame
  // stays 30 ms of flight unless steps_per_frame says otherwise.
  if (auto fidelity = sim->located_string("fidelity")) {
    if (sim->find("dt")) sim->fail("fidelity", "dt is given too: give the step in one place");
    try {
      s.dt = dt_of(parse_fidelity(fidelity->value));
    } catch (const std::invalid_argument& e) {
      io::fail(fidelity->where, e.what());
    }
    s.steps_per_frame = steps_in(kFrameSeconds, s.dt);
  }
  s.dt = sim->number("dt", s.dt, kDt);
  s.steps_per_frame = static_cast<uint32_t>(
      sim->integer("steps_per_frame", s.steps_per_frame, 1, kMaxStepsPerFrame));
  s.duration = sim->number("duration", s.duration, kDuration);
  s.seed = static_cast<uint64_t>(sim->integer("seed", static_cast<int64_t>(s.seed), 0));
  if (auto turning = sim->located_string("turning")) {
    if (turning->value == "tail")
      s.world.turning = TurningModel::tail;
    else if (turning->value == "fixed-rate")
      s.world.turning = TurningModel::fixed_rate;
    else
      io::fail(turning->where,
               "expected \"tail\" or \"fixed-rate\", got \"" + turning->value + "\"");
  }
  s.world.wind = L.vec3(*sim, "wind", s.world.wind, kVelocity);
}

// [wind]: the wind at a reference height and how it grows with height (world.h: WindProfile).
void read_wind(const TableReader& top, const Lengths& L, World& world) {
  const auto wind = top.table("wind", kWindKeys);
  if (!wind) return;
  const auto shorthand = top.table("simulation", kSimulationKeys);
  if (shorthand && shorthand->find("wind"))
    shorthand->fail("wind", "the wind is set in [wind] too: give it in one place");
  world.wind = L.vec3(*wind, "velocity", world.wind, kVelocity);
  if (auto profile = wind->located_string("profile")) {
    if (profile->value == "uniform")
      world.wind_profile = WindProfile::uniform;
    else if (profile->value == "power-law")
      world.wind_profile = WindProfile::power_law;
    else if (profile->value == "logarithmic")
      world.wind_profile = WindProfile::logarithmic;
    else
      io::fail(profile->where, "expected \"uniform\", \"power-law\" or \"logarithmic\", got \"" +
                                   profile->value + "\"");
  }
  world.wind_height = L.number(*wind, "height", world.wind_height, kLength);
  world.wind_exponent = wind->number("exponent", world.wind_exponent, io::between(0.0, 1.0));
  world.wind_roughness = L.number(*wind, "roughness", world.wind_roughness, kLength);
  if (world.wind_roughness >= world.wind_height)
    wind->fail(wind->find("roughness") ? "roughness" : "height",
               "the roughness length must be below the reference height");
}

void read_ground(const TableReader& top, const Lengths& L, World& world) {
  const auto ground = top.table("ground", kGroundKeys);
  if (!ground) return;
  world.ground_height = L.number(*ground, "height", world.ground_height, kPosition);
  world.ground_effect = ground->boolean("effect", world.ground_effect);
}

// Where `word` first stands as a whole word (an identifier) in `text`, or npos.
size_t find_word(std::string_view text, std::string_view word) {
  auto is_word_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  };
  for (size_t at = text.find(word); at != std::string_view::npos; at = text.find(word, at + 1)) {
    const size_t end = at + word.size();
    if ((at == 0 || !is_word_char(text[at - 1])) &&
        (end == text.size() || !is_word_char(text[end])))
      return at;
  }
  return std::string_view::npos;
}

// Runs the model's validate(Species) and reports its complaint at the field it names: the first
// field named in the message that this table sets, else the table itself.
void validate_species(const TableReader& r, const Species& s) {
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    std::string_view field;
    size_t field_at = std::string::npos;
    for (const io::SpeciesField& f : io::species_fields()) {
      const size_t at = find_word(what, f.name);
      if (at < field_at && r.find(f.name)) {
        field = f.name;
        field_at = at;
      }
    }
    if (field.empty())
      io::fail(
          r.where(),
          what + (r.find("base") ? "" : " (without a base, the fields of Table 1 start at 0)"));
    r.fail(field, what + ", got " + io::describe(*r.find(field)));
  }
}

// The names of the scenario's species, targets, branches, routes and flocks, as read so far.
struct Known {
  io::Names species{"species"}, targets{"target"}, branches{"branch"}, routes{"route"},
      flocks{"flock"};
};

// The required, unique `name` of a table (species, target, branch, route), added to `names`.
std::string unique_name(const TableReader& r, io::Names& names) {
  r.require("name");
  const LocatedString name = *r.located_string("name");
  names.add(name);
  return name.value;
}

// Fails at `key` (a point of the world) unless `y` is above the ground, or on it where `on` allows.
void check_above_ground(const TableReader& r, std::string_view key, std::string_view what, double y,
                        const World& world, const Lengths& L, bool on = false) {
  if (!above_ground(y, world, on))
    r.fail(key, std::string(what) + ", y = " + L.text(y) + ", must be " + (on ? "on or " : "") +
                    "above the ground at " + L.text(world.ground_height));
}

// A [[species]] table: a copy of `base` (a preset or an earlier species) with fields overridden.
Species read_species(const TableReader& r, const std::vector<Species>& known, io::Names& names) {
  Species s;
  // The base first: a species cannot be its own.
  if (auto base = r.located_string("base")) s = known[names.index(*base)];
  s.name = unique_name(r, names);
  // Each field's range is species.def's, checked by validate() below.
  for (const io::SpeciesField& f : io::species_fields())
    if (r.find(f.name)) s.*f.member = from_unit(r.number(f.name, 0.0, kAnyFinite), f.unit);
  validate_species(r, s);
  return s;
}

Target read_target(const TableReader& r, const Lengths& L, const World& world, io::Names& names) {
  Target t;
  t.name = unique_name(r, names);
  r.require("centre");
  t.centre = L.vec3(r, "centre", t.centre, kPosition);
  // A target may lie on the ground (Fig. 17 descends to one), not in it.
  check_above_ground(r, "centre", "a target's centre", t.centre.y, world, L, true);
  t.radius = L.number(r, "radius", t.radius, kLength);
  t.velocity = L.vec3(r, "velocity", t.velocity, kVelocity);
  t.amplitude = L.vec3(r, "amplitude", t.amplitude, kPosition);
  t.period =
      r.number("period", t.period, {kMinTargetPeriod, kMaxDuration, false, true, "11.6 days"});
  return t;
}

Branch read_branch(const TableReader& r, const Lengths& L, const World& world, io::Names& names) {
  Branch b;
  b.name = unique_name(r, names);
  r.require("point");
  b.point = L.vec3(r, "point", b.point, kPosition);
  // One on the ground is a landing site there (the feet meet the ground at the point).
  check_above_ground(r, "point", "a branch's point", b.point.y, world, L, true);
  const glm::dvec3 d = r.vec3("direction", b.direction, kAnyFinite);
  const double horizontal = std::hypot(d.x, d.z);
  // Horizontal-ish: at most about 6 degrees out of the horizontal plane.
  if (!(horizontal > 0) || std::abs(d.y) > 0.1 * horizontal)
    r.fail("direction", "expected a non-zero horizontal direction [x, 0, z]");
  b.direction = glm::dvec3(d.x / horizontal, 0.0, d.z / horizontal);
  b.length = L.number(r, "length", b.length, kLength);
  return b;
}

Route read_route(const TableReader& r, Known& known) {
  Route route;
  route.name = unique_name(r, known.routes);
  for (const LocatedString& target : r.strings("targets"))
    route.targets.push_back(known.targets.index(target));
  route.loop = r.boolean("loop", route.loop);
  if (auto branch = r.located_string("branch"))
    route.branch = static_cast<int32_t>(known.branches.index(*branch));
  route.path_control = r.boolean("path_control", route.path_control);
  if (route.targets.empty() && route.branch < 0)
    r.fail("targets", "expected at least one target name (or a branch to land on)");
  if (route.loop && route.targets.size() < 2)
    r.fail("loop", "a looping route needs at least two targets");
  if (route.loop && route.branch >= 0) r.fail("loop", "a route that lands on a branch cannot loop");
  return route;
}

Flock read_flock(const TableReader& r, size_t index, const Scenario& s, const Lengths& L,
                 Known& known) {
  r.require("species");
  r.require("route");
  Flock f;
  const auto name = r.located_string("name");
  f.name = name ? name->value : "flock" + std::to_string(index);
  if (name)
    known.flocks.add(*name);
  else
    known.flocks.add(f.name);
  f.species = known.species.index(*r.located_string("species"));
  f.route = known.routes.index(*r.located_string("route"));
  f.count = static_cast<uint32_t>(r.integer("count", f.count, 1, UINT32_MAX));
  f.spawn_centre = L.vec3(r, "centre", f.spawn_centre, kPosition);
  f.spawn_extent = L.vec3(r, "extent", f.spawn_extent, io::non_negative(kWorldRadius, kWorldWhy));
  f.heading = radians(r.number("heading", degrees(f.heading), io::magnitude(360.0, "a turn")));
  f.speed = L.number(r, "speed", f.speed, io::non_negative(kMaxSpeed, kSpeedWhy));
  // The initial wingbeat, clamped to the species' range: species.def's largest.
  f.frequency = r.number("frequency", f.frequency, io::non_negative(1000.0));
  f.amplitude = r.number("amplitude", f.amplitude, io::non_negative(10.0));
  f.standing = r.boolean("standing", f.standing);
  f.takeoff_time =
      r.number("takeoff_time", f.takeoff_time, io::non_negative(kMaxDuration, "11.6 days"));
  f.random_phase = r.boolean("random_phase", f.random_phase);
  f.flocking = r.boolean("flocking", f.flocking);
  // A flock of a species that flies in formation (w_formation > 0, the migrants) meets the wakes
  // unless told not to; the others only when told (docs/MODEL.md "The wake").
  f.wake = r.boolean("wake", f.flocking && s.species[f.species].w_formation > 0.0);
  if (f.wake && !f.flocking)
    r.fail("wake",
           "a bird meets the wakes of the birds it sees: wake = true needs flocking = true");
  // Nothing starts under the ground (validate() checks the same, unlocated): a standing flock
  // stands at its species' stand_height whatever its centre, a flying one anywhere in its box.
  const Species& sp = s.species[f.species];
  if (f.standing && !takeoff_counts(f.takeoff_time, s.dt))
    r.fail("takeoff_time", "more than 2^32 - 1 steps of dt (" + std::to_string(s.dt) +
                               " s): the wait is counted in whole steps");
  if (f.standing && !(sp.stand_height > 0.0))
    r.fail("standing",
           "species '" + sp.name + "' has stand_height 0: its birds would stand in the ground");
  if (!f.standing)
    check_above_ground(
        r, r.find("centre") ? "centre" : "extent", "the spawn box's lowest point, centre - extent",
        f.spawn_centre.y - spawn_extent(f, sp, f.count, s.world.ground_height).y, s.world, L);
  return f;
}

// Reads each [[key]] table in order, each seeing the items read before it.
template <class T, class Read>
void read_all(const TableReader& top, std::string_view key, Keys keys, std::vector<T>& items,
              Read read) {
  for (const TableReader& r : top.tables(key, keys)) items.push_back(read(r));
}

}  // namespace

Scenario parse_scenario(std::string_view text, std::string_view source_name) {
  if (text.size() > kMaxScenarioBytes)
    io::fail({source_name, {}, ""}, "the scenario is larger than " +
                                        std::to_string(kMaxScenarioBytes) +
                                        " bytes (16 MiB), the most a scenario may be");
  toml::table doc;
  try {
    doc = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    std::string what(e.description());  // toml++ says "Error while parsing ...: ..."
    if (what.starts_with("Error while")) what.replace(0, 5, "syntax error");
    io::fail({source_name, e.source(), ""}, what);
  }
  const TableReader top(source_name, doc, "", kTopKeys);
  Scenario s;
  s.hash = text_hash(text);
  const Lengths lengths = read_units(top);
  read_simulation(top, source_name, lengths, s);
  read_wind(top, lengths, s.world);
  read_ground(top, lengths, s.world);
  Known known;
  s.species = species_presets();
  for (const Species& preset : s.species) known.species.add(preset.name);
  read_all(top, "species", species_keys(), s.species,
           [&](const TableReader& r) { return read_species(r, s.species, known.species); });
  World& w = s.world;
  read_all(top, "targets", kTargetKeys, w.targets,
           [&](const TableReader& r) { return read_target(r, lengths, w, known.targets); });
  read_all(top, "branches", kBranchKeys, w.branches,
           [&](const TableReader& r) { return read_branch(r, lengths, w, known.branches); });
  read_all(top, "routes", kRouteKeys, w.routes,
           [&](const TableReader& r) { return read_route(r, known); });
  read_all(top, "flocks", kFlockKeys, s.flocks,
           [&](const TableReader& r) { return read_flock(r, s.flocks.size(), s, lengths, known); });
  // Targets start at their centres (target_position at t = 0).
  for (const Target& t : w.targets) w.target_now.push_back(t.centre);
  try {
    validate(s);
  } catch (const std::invalid_argument& e) {
    io::fail({source_name, {}, ""}, e.what());
  }
  return s;
}

Scenario read_scenario_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  auto cannot_read = [&](std::string_view why) {
    io::fail({name, {}, ""}, "cannot read the scenario file: " + std::string(why));
  };
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) cannot_read(ec.message());
  if (std::filesystem::is_directory(status)) cannot_read("it is a directory");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    cannot_read("it is not a regular file (a device, a pipe or a socket)");
  std::ifstream in(path, std::ios::binary);
  if (!in) cannot_read(std::strerror(errno));
  const std::string limit =
      std::to_string(kMaxScenarioBytes) + " bytes (16 MiB) a scenario file may be";
  if (const auto size = std::filesystem::file_size(path, ec); !ec && size > kMaxScenarioBytes)
    cannot_read("it is " + std::to_string(size) + " bytes, more than the " + limit);
  // Read in chunks up to the limit, whatever the size said: the file may grow meanwhile.
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
    if (text.size() > kMaxScenarioBytes) cannot_read("it is more than the " + limit);
  }
  if (in.bad()) cannot_read("read error");
  return parse_scenario(text, name);
}

}  // namespace aeroflock
