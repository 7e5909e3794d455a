#include "io/summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "model/constants.h"
#include "model/flock_geometry.h"
#include "model/route.h"

namespace aeroflock {
namespace {

bool in_the_air(FlightMode mode) {
  return mode == FlightMode::flying || mode == FlightMode::landing ||
         mode == FlightMode::taking_off;
}

}  // namespace

std::string WindWarning::sentence() const {
  char against_it[64] = "";
  if (against > 0.0)
    std::snprintf(against_it, sizeof against_it, " and %.1f m/s against it", against / 100.0);
  char text[512];
  std::snprintf(text, sizeof text,
                "flock \"%s\" cannot hold its leg from %s to \"%s\": at %.0f m the wind blows "
                "%.1f m/s across it%s, and its birds fly at %.1f m/s; they head into it and drift",
                flock.c_str(), from.empty() ? "its spawn" : ("\"" + from + "\"").c_str(),
                target.c_str(), height / 100.0, across / 100.0, against_it, airspeed / 100.0);
  return text;
}

std::vector<WindWarning> wind_warnings(const Scenario& scenario) {
  std::vector<WindWarning> warnings;
  for (const WindBeyondAirspeed& w : wind_beyond_airspeed(scenario))
    warnings.push_back(
        {scenario.flocks[w.flock].name,
         w.from == WindBeyondAirspeed::kSpawn ? "" : scenario.world.targets[w.from].name,
         scenario.world.targets[w.target].name, w.across, w.against, w.height, w.airspeed});
  return warnings;
}

FlockStatistics flock_statistics(const std::vector<BirdState>& birds,
                                 const std::vector<Species>& species) {
  FlockStatistics s;
  s.birds = birds.size();
  const FlockExtent extent = flock_extent(birds);
  s.centroid = extent.centre;
  s.nan_birds = s.birds - extent.finite;
  double speed_sum = 0.0;
  for (const BirdState& b : birds) {
    s.targets_reached += b.targets_reached;
    if (b.mode == FlightMode::perched)
      ++(b.species < species.size() && lands_on_ground(species[b.species]) ? s.landed : s.perched);
    s.flying += in_the_air(b.mode);
    if (is_finite(b)) speed_sum += glm::length(b.velocity);
  }
  if (extent.finite > 0) s.mean_speed = speed_sum / static_cast<double>(extent.finite);
  return s;
}

std::vector<FlockingSummary> flocking_summary(const Scenario& scenario,
                                              const std::vector<BirdState>& birds) {
  std::vector<FlockingSummary> out;
  for (uint32_t f = 0; f < scenario.flocks.size(); ++f) {
    if (!scenario.flocks[f].flocking) continue;
    std::vector<uint32_t> members;
    for (uint32_t i = 0; i < birds.size(); ++i)
      if (birds[i].flock == f) members.push_back(i);
    out.push_back({scenario.flocks[f].name, members.empty()
                                                ? FlockMetrics{}
                                                : flock_metrics(birds, scenario.species, members)});
  }
  return out;
}

std::vector<QuarantinedBird> quarantined_birds(const std::vector<BirdState>& birds, double dt,
                                               size_t most) {
  std::vector<QuarantinedBird> out;
  for (uint64_t i = 0; i < birds.size(); ++i)
    if (const BirdState& b = birds[i]; b.mode == FlightMode::quarantined)
      out.push_back({i, b.quarantined_step, double(b.quarantined_step) * dt, b});
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.step < b.step; });
  if (out.size() > most) out.resize(most);
  return out;
}

nlohmann::ordered_json summary_json(const RunSummary& r) {
  const FlockStatistics& s = r.stats;
  const double bird_steps = static_cast<double>(s.birds) * static_cast<double>(r.steps);
  nlohmann::ordered_json flocking = nlohmann::ordered_json::array();
  for (const FlockingSummary& f : r.flocking)
    flocking.push_back({{"name", f.name},
                        {"birds", f.metrics.birds},
                        {"median_nearest", f.metrics.median_nearest},
                        {"too_close", f.metrics.too_close},
                        {"polarisation", f.metrics.polarisation},
                        {"largest_cluster", f.metrics.largest_cluster}});
  nlohmann::ordered_json structure = nlohmann::ordered_json::array();
  for (const FlockStructureSummary& f : r.structure) {
    const StructureFigures& m = f.structure.mean;
    // null: a flock that neither meets wakes nor flies in formation
    nlohmann::ordered_json formation;
    if (f.formation)
      formation = {{"optimum_lateral", f.formation->optimum},
                   {"samples", f.formation->samples},
                   {"followers", f.formation->followers()},
                   {"in_v", f.formation->in_v()},
                   {"in_phase", f.formation->in_phase()},
                   {"behind", f.formation->behind()},
                   {"anti_phase", f.formation->anti_phase()},
                   {"head_power", f.formation->head_power_w()},
                   {"follower_power", f.formation->follower_power_w()},
                   {"in_v_power", f.formation->in_v_power_w()}};
    structure.push_back(
        nlohmann::ordered_json{{"flock", f.flock},
                               {"species", f.species},
                               {"wingspan", f.wingspan},
                               {"from", f.from},
                               {"to", f.to},
                               {"every", f.every},
                               {"first", f.structure.first},
                               {"last", f.structure.last},
                               {"samples", f.structure.samples},
                               {"birds", m.birds},
                               {"median_nearest", m.median_nearest},
                               {"median_nearest_wingspans", m.median_nearest_wingspans},
                               {"thickness", m.thickness},
                               {"width", m.width},
                               {"length", m.length},
                               {"thickness_over_length", m.thickness_over_length},
                               {"width_over_length", m.width_over_length},
                               {"thinnest_from_vertical", degrees(m.thinnest_from_vertical)},
                               {"motion_on_axes",
                                {{"thickness", m.motion_on_axes[0]},
                                 {"width", m.motion_on_axes[1]},
                                 {"length", m.motion_on_axes[2]}}},
                               {"border_fraction", m.border_fraction},
                               {"border_over_interior_nearest", m.border_over_interior},
                               {"anisotropy", m.anisotropy},
                               {"nearest_along_motion", m.nearest_along_motion},
                               {"formation", formation}});
  }
  nlohmann::ordered_json quarantined = nlohmann::ordered_json::array();
  for (const QuarantinedBird& q : r.quarantined) {
    const BirdState& b = q.last;
    quarantined.push_back({{"bird", q.bird},
                           {"step", q.step},
                           {"time", q.time},
                           {"position", {b.position.x, b.position.y, b.position.z}},
                           {"velocity", {b.velocity.x, b.velocity.y, b.velocity.z}},
                           {"attitude", {b.attitude.w, b.attitude.x, b.attitude.y, b.attitude.z}}});
  }
  nlohmann::ordered_json wind = nlohmann::ordered_json::array();
  for (const WindWarning& w : r.wind)
    wind.push_back(
        {{"flock", w.flock},
         {"from", w.from.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(w.from)},
         {"target", w.target},
         {"across_wind", w.across},
         {"against_wind", w.against},
         {"height", w.height},
         {"airspeed", w.airspeed}});
  // The file's units (the printed summary's are m and m/s): every quantity named with its unit.
  const nlohmann::ordered_json units = {
      {"dt", "s"},
      {"sim_seconds", "s"},
      {"wall_seconds", "s"},
      {"bird_steps_per_second", "1/s"},
      {"centroid", "cm (world frame, y up)"},
      {"mean_speed", "cm/s"},
      {"flocking.median_nearest", "cm"},
      {"flocking.too_close", "fraction of the flock's birds"},
      {"flocking.polarisation", "0 to 1"},
      {"flocking.largest_cluster", "fraction of the flock's birds"},
      {"structure.wingspan", "cm"},
      {"structure.from",
       "s: the window asked for, a snapshot at the first frame at or after each from + k every"},
      {"structure.to", "s"},
      {"structure.every", "s"},
      {"structure.first", "s: the first snapshot"},
      {"structure.last", "s: the last snapshot"},
      {"structure.birds", "mean birds measured a snapshot"},
      {"structure.median_nearest", "cm: r1, each snapshot's median, averaged"},
      {"structure.median_nearest_wingspans", "r1 in the species' wingspans"},
      {"structure.thickness", "cm: I1, along the thinnest principal axis"},
      {"structure.width", "cm: I2"},
      {"structure.length", "cm: I3"},
      {"structure.thinnest_from_vertical", "degrees"},
      {"structure.motion_on_axes", "|cos| of the angle between the mean velocity and each axis"},
      {"structure.border_fraction", "fraction of the flock's birds on its alpha-shape border"},
      {"structure.border_over_interior_nearest",
       "median r1 at the border over the interior's (< 1: denser border)"},
      {"structure.anisotropy", "gamma(n) for n = 1.., 1/3 isotropic"},
      {"structure.nearest_along_motion",
       "mean squared cosine of the nearest neighbour's direction with the motion, 1/3 isotropic"},
      {"structure.formation.optimum_lateral",
       "cm: the lateral offset of centres where a follower one span behind meets the most upwash"},
      {"structure.formation.followers",
       "mean birds a snapshot with another ahead within 10 spans (the nearest: the one followed)"},
      {"structure.formation.in_v",
       "fraction of the followers 30-60 degrees behind its wing, lateral within 10 % of the "
       "optimum"},
      {"structure.formation.in_phase",
       "fraction of those in V whose phase lag is within pi/4 of 2 pi f dx / U"},
      {"structure.formation.behind",
       "fraction of the followers directly behind (lateral within a quarter span)"},
      {"structure.formation.anti_phase",
       "fraction of those directly behind whose phase lag is within pi/4 of 2 pi f dx / U + pi"},
      {"structure.formation.head_power",
       "W: the wings' power against their motion of a bird that follows none, on average over "
       "every frame of the window (null over many ranks)"},
      {"structure.formation.follower_power", "W: the same of a follower"},
      {"structure.formation.in_v_power", "W: the same of a follower in a V place"},
      {"quarantined.time", "s"},
      {"quarantined.position", "cm"},
      {"quarantined.velocity", "cm/s"},
      {"quarantined.attitude", "quaternion w, x, y, z, body to world"},
      {"wind_beyond_airspeed.across_wind", "cm/s"},
      {"wind_beyond_airspeed.against_wind", "cm/s"},
      {"wind_beyond_airspeed.height", "cm (world y)"},
      {"wind_beyond_airspeed.airspeed", "cm/s"},
      {"ranks.bytes_sent", "bytes of migrants and ghosts"},
      {"ranks.communication_seconds", "s of wall time in the exchanges"},
  };
  nlohmann::ordered_json ranks = nlohmann::ordered_json();
  for (const RankSummary& k : r.ranks)
    ranks.push_back({{"rank", k.rank},
                     {"birds", k.birds},
                     {"ghosts", k.ghosts},
                     {"migrants_sent", k.migrants_sent},
                     {"ghosts_sent", k.ghosts_sent},
                     {"bytes_sent", k.bytes_sent},
                     {"rebalances", k.rebalances},
                     {"communication_seconds", k.communication_seconds}});
  return {
      {"units", units},
      {"backend", r.backend},
      {"device", r.device},
      {"scenario", r.scenario},
      {"scenario_hash", r.scenario_hash},
      {"birds", s.birds},
      {"steps", r.steps},
      {"dt", r.dt},
      {"steps_per_frame", r.steps_per_frame},
      {"sim_seconds", r.sim_seconds},
      {"interrupted", r.interrupted},
      {"wall_seconds", r.wall_seconds},
      {"bird_steps_per_second", r.wall_seconds > 0 ? bird_steps / r.wall_seconds : 0.0},
      {"nan_birds", s.nan_birds},
      {"centroid", {s.centroid.x, s.centroid.y, s.centroid.z}},
      {"mean_speed", s.mean_speed},
      {"targets_reached", s.targets_reached},
      {"perched", s.perched},
      {"landed", s.landed},
      {"flying", s.flying},
      {"flocking", flocking},
      {"structure", structure},
      {"quarantined", quarantined},
      {"signal", r.signal.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(r.signal)},
      {"error", r.error.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(r.error)},
      {"wind_beyond_airspeed", wind},
      {"ranks", ranks},
      {"vtk_queue", r.vtk_queue_bound == 0
                        ? nlohmann::ordered_json()
                        : nlohmann::ordered_json{{"high_water_frames", r.vtk_queue_frames},
                                                 {"high_water_bytes", r.vtk_queue_bytes},
                                                 {"bound_frames", r.vtk_queue_bound}}},
  };
}

void write_summary(const std::filesystem::path& path, const RunSummary& summary) {
  write_text_atomically(path, summary_json(summary).dump(2) + "\n");
}

}  // namespace aeroflock
