#include "envelope.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "backend.h"
#include "io/atomic_file.h"
#include "io/paths.h"
#include "io/scenario_file.h"
#include "model/constants.h"
#include "progress.h"
#include "run/fly_envelope.h"

namespace aeroflock {
namespace {

// "eagle, starling, ...": the presets' names, for the help and the error.
std::string preset_names() {
  std::string names;
  for (const Species& s : species_presets()) names += (names.empty() ? "" : ", ") + s.name;
  return names;
}

Species species_named(const std::string& name) {
  if (name.size() > 5 && name.ends_with(".toml")) {
    const Scenario s = read_scenario_file(name);
    if (s.species.size() <= species_presets().size())  // the file's own follow the presets
      throw std::runtime_error("--species " + name +
                               ": the file has no [[species]] table (the envelope flies its last)");
    return s.species.back();
  }
  for (const Species& s : species_presets())
    if (s.name == name) return s;
  throw std::runtime_error("--species: no preset named \"" + name + "\" (" + preset_names() +
                           ", or a FILE.toml)");
}

// One row of a table: how many of the cases with this value of a dimension succeed.
struct Tally {
  int reached = 0, total = 0;
  std::map<std::string, int> failures;  // by outcome
};

void print_table(const char* dimension, const std::map<std::string, Tally>& rows) {
  std::printf("\nby %s:\n", dimension);
  for (const auto& [value, t] : rows) {
    std::printf("  %-22s %5d / %-5d", value.c_str(), t.reached, t.total);
    for (const auto& [outcome, n] : t.failures) std::printf("  %s %d", outcome.c_str(), n);
    std::printf("\n");
  }
}

std::string kind_name(EnvelopeCase::Kind k) {
  return k == EnvelopeCase::Kind::flight    ? "flight"
         : k == EnvelopeCase::Kind::takeoff ? "takeoff"
                                            : "landing";
}

// The touch-downs of the cases (issue 40's measures, model/touchdown.h), on the branch (a ground
// lander's site) or on the ground: how many, the largest jump into the grip, mean speed before it,
// speed fall and body turn after it, and the go-rounds of the landings.
void print_touchdowns(const std::vector<EnvelopeResult>& results, const Species& species) {
  for (const bool branch : {true, false}) {
    int n = 0;
    Touchdown worst;
    size_t go_rounds = 0;
    for (const EnvelopeResult& r : results) {
      if (r.c.kind == EnvelopeCase::Kind::landing && branch) go_rounds += r.go_rounds;
      if (!r.touchdown || r.touchdown->on_branch != branch) continue;
      ++n;
      worst.jump = std::max(worst.jump, r.touchdown->jump);
      worst.reach = std::max(worst.reach, r.touchdown->reach);
      worst.mean_speed = std::max(worst.mean_speed, r.touchdown->mean_speed);
      worst.speed_fall = std::max(worst.speed_fall, r.touchdown->speed_fall);
      worst.turn_rate = std::max(worst.turn_rate, r.touchdown->turn_rate);
      worst.turn_jump = std::max(worst.turn_jump, r.touchdown->turn_jump);
    }
    if (n == 0) continue;
    std::printf(
        "  %-22s %5d  jump <= %.1f cm (body %.1f deg), mean speed before <= %.2f m/s, "
        "speed falls <= %.0f m/s2, body turns <= %.0f deg/s",
        branch ? (species.perches != 0.0 ? "on the branch" : "at the site") : "on the ground", n,
        worst.jump, degrees(worst.turn_jump), worst.mean_speed / 100, worst.speed_fall / 100,
        degrees(worst.turn_rate));
    if (branch) std::printf(", feet <= %.1f cm from the branch point", worst.reach);
    if (branch) std::printf(", %zu go-rounds", go_rounds);
    std::printf("\n");
  }
}

nlohmann::json touchdown_json(const EnvelopeResult& r) {
  if (!r.touchdown) return nullptr;
  const Touchdown& d = *r.touchdown;
  return {{"on_branch", d.on_branch},
          {"time_s", d.time},
          {"jump_cm", d.jump},
          {"reach_cm", d.reach},
          {"mean_speed_m_s", d.mean_speed / 100},
          {"window_s", d.window},
          {"speed_fall_m_s2", d.speed_fall / 100},
          {"turn_deg_s", degrees(d.turn_rate)},
          {"turn_jump_deg", degrees(d.turn_jump)}};
}

}  // namespace

int run_envelope(const EnvelopeOptions& options) {
  if (!options.json.empty()) check_output_path(options.json, "--json", {".json"});
  if (options.backend != "cpu" && options.backend != "vulkan")
    throw std::runtime_error("--backend: expected cpu or vulkan, got " + options.backend);
  const Species species = species_named(options.species);
  const std::vector<EnvelopeCase> cases = envelope_cases(options.quick);
  std::printf("aeroflock envelope: %s, %zu cases on the %s backend, dt %g s\n",
              species.name.c_str(), cases.size(), options.backend.c_str(), options.dt);
  std::fflush(stdout);

  const SimulationFactory make = simulation_factory(options.backend, options.device);
  Progress progress;
  const std::vector<EnvelopeResult> results = fly_envelope(
      species, cases, make,
      [&](double t) {
        if (progress.due()) progress.show("t = " + std::to_string(int(t)) + " s");
      },
      options.dt);
  progress.finish();

  std::map<std::string, Tally> by_kind, by_speed, by_pitch, by_bank, by_rise, by_bearing,
      by_distance, by_wind;
  int reached = 0;
  for (const EnvelopeResult& r : results) {
    const bool ok = r.outcome == Outcome::reached;
    reached += ok;
    auto count = [&](std::map<std::string, Tally>& rows, const std::string& value) {
      Tally& t = rows[value];
      ++t.total;
      if (ok)
        ++t.reached;
      else
        ++t.failures[name(r.outcome)];
    };
    auto fmt = [](const char* f, double v) {
      char text[32];
      std::snprintf(text, sizeof text, f, v);
      return std::string(text);
    };
    count(by_kind, kind_name(r.c.kind));
    count(by_wind, fmt("%2.0f m/s", r.c.crosswind / 100));
    if (r.c.kind != EnvelopeCase::Kind::flight) continue;
    count(by_speed, fmt("%2.0f m/s", r.c.speed / 100));
    count(by_pitch, fmt("%+3.0f deg", degrees(r.c.pitch)));
    count(by_bank, fmt("%+3.0f deg", degrees(r.c.bank)));
    count(by_rise, fmt("%+4.0f m", r.c.rise / 100));
    count(by_bearing, fmt("%3.0f deg", degrees(r.c.bearing)));
    count(by_distance, fmt("%5.0f m", r.c.distance / 100));
  }
  std::printf("\n%d of %zu cases succeed\n", reached, results.size());
  print_table("kind", by_kind);
  print_table("crosswind", by_wind);
  print_table("start speed (flights)", by_speed);
  print_table("start pitch (flights)", by_pitch);
  print_table("start bank (flights)", by_bank);
  print_table("target height (flights)", by_rise);
  print_table("target bearing (flights)", by_bearing);
  print_table("target distance (flights)", by_distance);
  std::printf("\ntouch-downs (30 ms frames):\n");
  print_touchdowns(results, species);
  int shown = 0;
  for (const EnvelopeResult& r : results)
    if (r.outcome != Outcome::reached && shown++ < 10)
      std::printf("%s  %s: %s at %.1f s (bank %.0f, pitch %.0f deg, lowest %.1f m)\n",
                  shown == 1 ? "\nfailing, e.g.\n" : "", r.c.describe().c_str(), name(r.outcome),
                  r.time, degrees(r.worst_bank), degrees(r.worst_pitch), r.lowest / 100);

  if (!options.json.empty()) {
    nlohmann::json j = {{"species", species.name},
                        {"backend", options.backend},
                        {"cases", results.size()},
                        {"reached", reached}};
    nlohmann::json list = nlohmann::json::array();
    for (const EnvelopeResult& r : results)
      list.push_back({{"kind", kind_name(r.c.kind)},
                      {"speed_m_s", r.c.speed / 100},
                      {"pitch_deg", degrees(r.c.pitch)},
                      {"bank_deg", degrees(r.c.bank)},
                      {"rise_m", r.c.rise / 100},
                      {"bearing_deg", degrees(r.c.bearing)},
                      {"distance_m", r.c.distance / 100},
                      {"crosswind_m_s", r.c.crosswind / 100},
                      {"outcome", name(r.outcome)},
                      {"time_s", r.time},
                      {"worst_bank_deg", degrees(r.worst_bank)},
                      {"worst_pitch_deg", degrees(r.worst_pitch)},
                      {"lowest_m", r.lowest / 100},
                      {"touchdown", touchdown_json(r)},
                      {"go_rounds", r.go_rounds}});
    j["results"] = list;
    write_text_atomically(options.json, j.dump(2) + "\n");
    std::printf("\njson     %s\n", options.json.c_str());
  }
  return reached == int(results.size()) ? 0 : 1;
}

Command add_envelope_command(CLI::App& app, EnvelopeOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "envelope", "Fly a species through a grid of starts, targets, winds, take-offs and landings");
  cmd->add_option("--species", o.species,
                  "A preset (" + preset_names() + ") or FILE.toml (its last [[species]])")
      ->capture_default_str();
  add_backend_option(cmd, o.backend);
  add_device_option(cmd, o.device);
  cmd->add_option("--json", o.json, "Write every case and its outcome to FILE")->check(kPath);
  cmd->add_flag("--quick", o.quick, "A small subset of short flights");
  auto step = std::make_shared<StepOption>();
  add_step_options(cmd, *step, "paper");
  return {cmd, [&o, step] {
            o.dt = step->value().value_or(kPaperDt);
            return run_envelope(o);
          }};
}

}  // namespace aeroflock
