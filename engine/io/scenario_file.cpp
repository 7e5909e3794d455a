#include "io/scenario_file.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "io/species_fields.h"
#include "io/toml_reader.h"
#include "model/constants.h"

namespace aeroflock {
namespace {

using io::LocatedString;
using io::Range;
using io::TableReader;

using Keys = std::span<const std::string_view>;

constexpr std::string_view kTopKeys[] = {"simulation", "ground",  "units",    "wind",  "species",
                                         "targets",    "branches", "routes", "flocks"};
constexpr std::string_view kUnitsKeys[] = {"length"};
constexpr std::string_view kWindKeys[] = {"velocity", "profile", "height", "exponent", "roughness"};
constexpr std::string_view kSimulationKeys[] = {
    "name", "description", "dt", "fidelity", "steps_per_frame", "duration", "seed", "turning", "wind"};
constexpr std::string_view kGroundKeys[] = {"height", "effect"};
constexpr std::string_view kTargetKeys[] = {"name",     "centre",    "radius",
                                            "velocity", "amplitude", "period"};
constexpr std::string_view kBranchKeys[] = {"name", "point", "direction", "length"};
constexpr std::string_view kRouteKeys[] = {"name", "targets", "loop", "branch", "path_control"};
constexpr std::string_view kFlockKeys[] = {
    "name",  "species",   "route",     "count",    "centre",       "extent",      "heading",
    "speed", "frequency", "amplitude", "standing", "takeoff_time", "random_phase", "flocking"};

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

  double number(const TableReader& r, std::string_view key, double fallback_cm, Range range = Range::any) const {
    return r.find(key) ? r.number(key, 0.0, range) * cm : fallback_cm;
  }
  glm::dvec3 vec3(const TableReader& r, std::string_view key, const glm::dvec3& fallback_cm,
                  Range range = Range::any) const {
    return r.find(key) ? r.vec3(key, glm::dvec3(0.0), range) * cm : fallback_cm;
  }
};

Lengths read_units(const TableReader& top) {
  Lengths l;
  const auto units = top.table("units", kUnitsKeys);
  if (!units) return l;
  const auto length = units->located_string("length");
  if (!length) return l;
  constexpr std::pair<std::string_view, double> kKnown[] = {{"mm", 0.1}, {"cm", 1.0}, {"m", 100.0}, {"km", 1.0e5}};
  for (const auto& [name, cm] : kKnown)
    if (length->value == name) return {cm};
  io::fail(length->where, "expected \"mm\", \"cm\", \"m\" or \"km\", got \"" + length->value + "\"");
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

void read_simulation(const TableReader& top, std::string_view source_name, const Lengths& L, Scenario& s) {
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
  s.dt = sim->number("dt", s.dt, Range::positive);
  s.steps_per_frame =
      static_cast<uint32_t>(sim->integer("steps_per_frame", s.steps_per_frame, 1, UINT32_MAX));
  s.duration = sim->number("duration", s.duration, Range::positive);
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
  s.world.wind = L.vec3(*sim, "wind", s.world.wind);
}

// [wind]: the wind at a reference height and how it grows with height (world.h: WindProfile).
void read_wind(const TableReader& top, const Lengths& L, World& world) {
  const auto wind = top.table("wind", kWindKeys);
  if (!wind) return;
  const auto shorthand = top.table("simulation", kSimulationKeys);
  if (shorthand && shorthand->find("wind"))
    shorthand->fail("wind", "the wind is set in [wind] too: give it in one place");
  world.wind = L.vec3(*wind, "velocity", world.wind);
  if (auto profile = wind->located_string("profile")) {
    if (profile->value == "uniform")
      world.wind_profile = WindProfile::uniform;
    else if (profile->value == "power-law")
      world.wind_profile = WindProfile::power_law;
    else if (profile->value == "logarithmic")
      world.wind_profile = WindProfile::logarithmic;
    else
      io::fail(profile->where, "expected \"uniform\", \"power-law\" or \"logarithmic\", got \"" + profile->value + "\"");
  }
  world.wind_height = L.number(*wind, "height", world.wind_height, Range::positive);
  world.wind_exponent = wind->number("exponent", world.wind_exponent, Range::non_negative);
  if (world.wind_exponent > 1.0) wind->fail("exponent", "expected a number within [0, 1], got " + io::describe(*wind->find("exponent")));
  world.wind_roughness = L.number(*wind, "roughness", world.wind_roughness, Range::positive);
  if (world.wind_roughness >= world.wind_height)
    wind->fail(wind->find("roughness") ? "roughness" : "height", "the roughness length must be below the reference height");
}

void read_ground(const TableReader& top, const Lengths& L, World& world) {
  const auto ground = top.table("ground", kGroundKeys);
  if (!ground) return;
  world.ground_height = L.number(*ground, "height", world.ground_height);
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
      io::fail(r.where(),
               what + (r.find("base") ? "" : " (without a base, the fields of Table 1 start at 0)"));
    r.fail(field, what + ", got " + io::describe(*r.find(field)));
  }
}

// The required, unique `name` of a table of `what`s (species, target, branch, route).
template <class T>
std::string unique_name(const TableReader& r, const std::vector<T>& known, const char* what) {
  r.require("name");
  const LocatedString name = *r.located_string("name");
  io::check_unique(known, name, what);
  return name.value;
}

// A [[species]] table: a copy of `base` (a preset or an earlier species) with fields overridden.
Species read_species(const TableReader& r, const std::vector<Species>& known) {
  const std::string name = unique_name(r, known, "species");
  Species s;
  if (auto base = r.located_string("base")) s = known[io::index_by_name(known, *base, "species")];
  s.name = name;
  for (const io::SpeciesField& f : io::species_fields())
    if (r.find(f.name)) s.*f.member = from_unit(r.number(f.name, 0.0), f.unit);
  validate_species(r, s);
  return s;
}

Target read_target(const TableReader& r, const Lengths& L, const std::vector<Target>& known) {
  Target t;
  t.name = unique_name(r, known, "target");
  r.require("centre");
  t.centre = L.vec3(r, "centre", t.centre);
  t.radius = L.number(r, "radius", t.radius, Range::positive);
  t.velocity = L.vec3(r, "velocity", t.velocity);
  t.amplitude = L.vec3(r, "amplitude", t.amplitude);
  t.period = r.number("period", t.period, Range::non_negative);
  return t;
}

Branch read_branch(const TableReader& r, const Lengths& L, const std::vector<Branch>& known) {
  Branch b;
  b.name = unique_name(r, known, "branch");
  r.require("point");
  b.point = L.vec3(r, "point", b.point);
  const glm::dvec3 d = r.vec3("direction", b.direction);
  const double horizontal = std::hypot(d.x, d.z);
  // Horizontal-ish: at most about 6 degrees out of the horizontal plane.
  if (!(horizontal > 0) || std::abs(d.y) > 0.1 * horizontal)
    r.fail("direction", "expected a non-zero horizontal direction [x, 0, z]");
  b.direction = glm::dvec3(d.x / horizontal, 0.0, d.z / horizontal);
  b.length = L.number(r, "length", b.length, Range::positive);
  return b;
}

Route read_route(const TableReader& r, const World& world) {
  Route route;
  route.name = unique_name(r, world.routes, "route");
  for (const LocatedString& target : r.strings("targets"))
    route.targets.push_back(io::index_by_name(world.targets, target, "target"));
  route.loop = r.boolean("loop", route.loop);
  if (auto branch = r.located_string("branch"))
    route.branch = static_cast<int32_t>(io::index_by_name(world.branches, *branch, "branch"));
  route.path_control = r.boolean("path_control", route.path_control);
  if (route.targets.empty() && route.branch < 0)
    r.fail("targets", "expected at least one target name (or a branch to land on)");
  if (route.loop && route.targets.size() < 2)
    r.fail("loop", "a looping route needs at least two targets");
  if (route.loop && route.branch >= 0)
    r.fail("loop", "a route that lands on a branch cannot loop");
  return route;
}

Flock read_flock(const TableReader& r, size_t index, const Scenario& s, const Lengths& L,
                 const std::vector<Flock>& known) {
  r.require("species");
  r.require("route");
  Flock f;
  const auto name = r.located_string("name");
  f.name = name ? name->value : "flock" + std::to_string(index);
  if (name) io::check_unique(known, *name, "flock");
  f.species = io::index_by_name(s.species, *r.located_string("species"), "species");
  f.route = io::index_by_name(s.world.routes, *r.located_string("route"), "route");
  f.count = static_cast<uint32_t>(r.integer("count", f.count, 1, UINT32_MAX));
  f.spawn_centre = L.vec3(r, "centre", f.spawn_centre);
  f.spawn_extent = L.vec3(r, "extent", f.spawn_extent, Range::non_negative);
  f.heading = radians(r.number("heading", degrees(f.heading)));
  f.speed = L.number(r, "speed", f.speed, Range::non_negative);
  f.frequency = r.number("frequency", f.frequency, Range::non_negative);
  f.amplitude = r.number("amplitude", f.amplitude, Range::non_negative);
  f.standing = r.boolean("standing", f.standing);
  f.takeoff_time = r.number("takeoff_time", f.takeoff_time, Range::non_negative);
  f.random_phase = r.boolean("random_phase", f.random_phase);
  f.flocking = r.boolean("flocking", f.flocking);
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
  s.species = species_presets();
  read_all(top, "species", species_keys(), s.species,
           [&](const TableReader& r) { return read_species(r, s.species); });
  World& w = s.world;
  read_all(top, "targets", kTargetKeys, w.targets,
           [&](const TableReader& r) { return read_target(r, lengths, w.targets); });
  read_all(top, "branches", kBranchKeys, w.branches,
           [&](const TableReader& r) { return read_branch(r, lengths, w.branches); });
  read_all(top, "routes", kRouteKeys, w.routes,
           [&](const TableReader& r) { return read_route(r, w); });
  read_all(top, "flocks", kFlockKeys, s.flocks,
           [&](const TableReader& r) { return read_flock(r, s.flocks.size(), s, lengths, s.flocks); });
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
  if (std::filesystem::is_directory(path, ec)) cannot_read("it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) cannot_read(std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) cannot_read("read error");
  return parse_scenario(text.str(), name);
}

}  // namespace aeroflock
