#include "io/scenario_file.h"

#include <cctype>
#include <cerrno>
#include <cmath>
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

constexpr std::string_view kTopKeys[] = {"simulation", "ground", "species", "targets",
                                         "branches",   "routes", "flocks"};
constexpr std::string_view kSimulationKeys[] = {
    "name", "description", "dt", "steps_per_frame", "duration", "seed", "turning", "wind"};
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

std::string stem(std::string_view source_name) {
  return std::filesystem::path(source_name).stem().string();
}

void read_simulation(const TableReader& top, std::string_view source_name, Scenario& s) {
  s.name = stem(source_name);
  const auto sim = top.table("simulation", kSimulationKeys);
  if (!sim) return;
  s.name = sim->string("name", s.name);
  s.description = sim->string("description", "");
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
  s.world.wind = sim->vec3("wind", s.world.wind);
}

void read_ground(const TableReader& top, World& world) {
  const auto ground = top.table("ground", kGroundKeys);
  if (!ground) return;
  world.ground_height = ground->number("height", world.ground_height);
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

Target read_target(const TableReader& r, const std::vector<Target>& known) {
  Target t;
  t.name = unique_name(r, known, "target");
  r.require("centre");
  t.centre = r.vec3("centre", t.centre);
  t.radius = r.number("radius", t.radius, Range::positive);
  t.velocity = r.vec3("velocity", t.velocity);
  t.amplitude = r.vec3("amplitude", t.amplitude);
  t.period = r.number("period", t.period, Range::non_negative);
  return t;
}

Branch read_branch(const TableReader& r, const std::vector<Branch>& known) {
  Branch b;
  b.name = unique_name(r, known, "branch");
  r.require("point");
  b.point = r.vec3("point", b.point);
  const glm::dvec3 d = r.vec3("direction", b.direction);
  const double horizontal = std::hypot(d.x, d.z);
  // Horizontal-ish: at most about 6 degrees out of the horizontal plane.
  if (!(horizontal > 0) || std::abs(d.y) > 0.1 * horizontal)
    r.fail("direction", "expected a non-zero horizontal direction [x, 0, z]");
  b.direction = glm::dvec3(d.x / horizontal, 0.0, d.z / horizontal);
  b.length = r.number("length", b.length, Range::positive);
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

Flock read_flock(const TableReader& r, size_t index, const Scenario& s,
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
  f.spawn_centre = r.vec3("centre", f.spawn_centre);
  f.spawn_extent = r.vec3("extent", f.spawn_extent, Range::non_negative);
  f.heading = radians(r.number("heading", degrees(f.heading)));
  f.speed = r.number("speed", f.speed, Range::non_negative);
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
  read_simulation(top, source_name, s);
  read_ground(top, s.world);
  s.species = species_presets();
  read_all(top, "species", species_keys(), s.species,
           [&](const TableReader& r) { return read_species(r, s.species); });
  World& w = s.world;
  read_all(top, "targets", kTargetKeys, w.targets,
           [&](const TableReader& r) { return read_target(r, w.targets); });
  read_all(top, "branches", kBranchKeys, w.branches,
           [&](const TableReader& r) { return read_branch(r, w.branches); });
  read_all(top, "routes", kRouteKeys, w.routes,
           [&](const TableReader& r) { return read_route(r, w); });
  read_all(top, "flocks", kFlockKeys, s.flocks,
           [&](const TableReader& r) { return read_flock(r, s.flocks.size(), s, s.flocks); });
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
