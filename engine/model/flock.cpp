#include "flock.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <tuple>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "body.h"
#include "constants.h"
#include "control.h"
#include "route.h"
#include "wingbeat.h"

namespace aeroflock {

using glm::dvec3;

namespace {

dvec3 unit_or_zero(const dvec3& v) {
  const double length = glm::length(v);
  return length > 0.0 ? v / length : dvec3{0.0};
}

// Where a bird flies through the air it flies in, moving with `wind`, and looks: along its air
// velocity (its head's direction while it is still in that air).
dvec3 flight_direction(const BirdState& b, const dvec3& wind) {
  const dvec3 air = b.velocity - wind;
  return glm::length(air) > 0.0 ? glm::normalize(air) : b.attitude * dvec3{1.0, 0.0, 0.0};
}

// The k nearest seen so far, nearest first, ties by index: one insertion step.
struct Nearest {
  uint32_t k;
  std::vector<uint32_t> index;
  std::vector<double> distance2;

  bool full() const { return index.size() >= k; }
  double worst2() const { return distance2.back(); }
  bool beats_worst(uint32_t j, double d2) const {
    return !full() || d2 < worst2() || (d2 == worst2() && j < index.back());
  }
  void offer(uint32_t j, double d2) {
    if (k == 0 || !beats_worst(j, d2)) return;
    size_t at = index.size();
    while (at > 0 && (distance2[at - 1] > d2 || (distance2[at - 1] == d2 && index[at - 1] > j)))
      --at;
    index.insert(index.begin() + static_cast<std::ptrdiff_t>(at), j);
    distance2.insert(distance2.begin() + static_cast<std::ptrdiff_t>(at), d2);
    if (index.size() > k) {
      index.pop_back();
      distance2.pop_back();
    }
  }
};

// Whether a species takes its k nearest from all round it (separation_all_round).
bool seeks_all_round(const Species& s) { return s.separation_all_round != 0.0; }

// Whether bird j is one bird i may see (before distance and the blind sector).
bool may_see(const BirdState& i, const BirdState& j) { return j.flock == i.flock && flocks_now(j); }

// Offers bird j to bird i's list if i sees it.
void consider(Nearest& nearest, const Species& s, const std::vector<BirdState>& birds, uint32_t i,
              uint32_t j, const dvec3& ahead) {
  if (j == i || !may_see(birds[i], birds[j])) return;
  const dvec3 offset = birds[j].position - birds[i].position;
  if (sees(s, ahead, offset)) nearest.offer(j, glm::dot(offset, offset));
}

}  // namespace

double zone_distance(const Species& s, const dvec3& offset, const dvec3& ahead) {
  const double along = glm::dot(offset, ahead);
  const double across2 = std::max(glm::dot(offset, offset) - along * along, 0.0);
  const double front = along / s.separation_front;
  return std::sqrt(across2 + front * front);
}

dvec3 nearest_offset(const Species& s, const dvec3& offset, const dvec3& closing) {
  const double closing2 = glm::dot(closing, closing);
  if (!(s.separation_lookahead > 0.0) || !(closing2 > 0.0)) return offset;
  const double t = std::clamp(-glm::dot(offset, closing) / closing2, 0.0, s.separation_lookahead);
  const dvec3 nearest = offset + closing * t;
  return glm::dot(nearest, offset) > 0.0 ? nearest : offset;
}

bool flocks_now(const BirdState& b) {
  return b.flocking != 0 && b.mode == FlightMode::flying && b.landing_stage == LandingStage::none;
}

bool outside_blind(const Species& s, const dvec3& ahead, const dvec3& offset) {
  // Blind within half the blind angle of straight back: cos(angle from straight back) > cos(blind /
  // 2).
  return -glm::dot(offset, ahead) <=
         std::cos(0.5 * s.blind_angle) * std::sqrt(glm::dot(offset, offset));
}

bool sees(const Species& s, const dvec3& ahead, const dvec3& offset) {
  if (glm::dot(offset, offset) > s.perception_radius * s.perception_radius) return false;
  return seeks_all_round(s) || outside_blind(s, ahead, offset);
}

uint32_t reaction_frames(const Species& s, double frame_seconds) {
  return static_cast<uint32_t>(std::max(1.0, std::floor(s.reaction_time / frame_seconds + 0.5)));
}

dvec3 route_direction(const Species& s, const dvec3& to_goal) {
  const dvec3 way = horizontal(to_goal);
  const double length = glm::length(way);
  if (length <= s.height_capture) return unit_or_zero(to_goal);
  return unit_or_zero(way * (s.height_capture / length) + dvec3{0.0, to_goal.y, 0.0});
}

dvec3 route_heading(const Species& s, const dvec3& to_goal, const dvec3& wind, double airspeed) {
  const dvec3 route = route_direction(s, to_goal);
  const dvec3 way = horizontal(route);
  const dvec3 aim = compensated_aim(way, track_aim(way, wind, airspeed), s.drift_compensation);
  const dvec3 level = glm::length(aim) > 0.0 ? glm::normalize(aim) * glm::length(way) : way;
  return level + dvec3{0.0, route.y, 0.0};
}

double cohesion_pull(const Species& s, const dvec3& cohesion, const dvec3& ahead) {
  const double weights = s.w_route + s.w_alignment + s.w_cohesion;
  return weights > 0.0 ? s.cruise_speed * s.w_cohesion * glm::dot(cohesion, ahead) / weights : 0.0;
}

Perception social_goal(const Species& s, const BirdState& b, const dvec3& wind,
                       const dvec3& route_goal, bool route_done, std::span<const uint32_t> seen,
                       const std::vector<BirdState>& birds, const Formation& formation) {
  Perception p;
  p.neighbours = static_cast<uint32_t>(seen.size());
  if (seen.empty()) return p;
  const dvec3 ahead = flight_direction(b, wind);
  dvec3 separation{0.0}, heading_sum{0.0}, cohesion_sum{0.0};
  double ahead_sum = 0.0, close_sum = 0.0, faster_sum = 0.0;
  int beyond = 0;
  uint32_t ahead_count = 0, heeded = 0;
  for (const uint32_t j : seen) {
    const dvec3 offset = birds[j].position - b.position;
    const double distance = glm::length(offset);
    const dvec3 nearest = nearest_offset(s, offset, birds[j].velocity - b.velocity);
    const double zone = zone_distance(s, nearest, ahead);
    if (zone < s.separation_radius)
      separation -= unit_or_zero(nearest) * std::pow(1.0 - zone / s.separation_radius, 2.0);
    if (seeks_all_round(s) && !outside_blind(s, ahead, offset)) continue;
    ++heeded;
    if (distance >= s.separation_radius) cohesion_sum += offset;
    heading_sum += unit_or_zero(birds[j].velocity - wind);
    if (glm::dot(offset, ahead) > 0.0) ++ahead_count;
    faster_sum += glm::dot(birds[j].velocity - b.velocity, ahead);
    // Along its flight, how far the neighbour is from separation_radius away (ahead > 0): one
    // nearer than that counts in full, those beyond by their mean.
    if (distance > 0.0) {
      const double along = glm::dot(offset, ahead) * (1.0 - s.separation_radius / distance);
      if (distance < s.separation_radius)
        close_sum += along;
      else
        ahead_sum += along, ++beyond;
    }
  }
  p.nearest = glm::length(birds[seen[0]].position - b.position);
  for (const uint32_t j : seen) p.seen_key += j * kSeenKeyFactor;
  const dvec3 route = route_done ? dvec3{0.0}
                                 : route_heading(s, route_goal - b.position, wind,
                                                 glm::length(horizontal(b.velocity - wind)));
  // A bird of a formation species that sees none of them ahead of it (along its flight) heads the
  // formation: it flies its route at its own airspeed, heeding only the separation. Steered by its
  // followers too (their cohesion, their speed), it and they swung each other's airspeed and
  // course, and each follower's swings grew down the chain behind it.
  if (s.w_formation > 0.0 && !route_done && ahead_count == 0) {
    p.airspeed = b.airspeed;
    p.direction = unit_or_zero(s.w_route * route + s.w_separation * separation);
    return p;
  }
  const double along_total = close_sum + (beyond > 0 ? ahead_sum / beyond : 0.0);
  const double faster = heeded > 0 ? faster_sum / double(heeded) : 0.0;
  const double pull = cohesion_pull(s, unit_or_zero(cohesion_sum), ahead);
  p.airspeed =
      std::clamp(s.cruise_speed + s.speed_gain * along_total + s.speed_match * faster + pull,
                 s.min_speed, s.max_speed);
  if (formation.heading != dvec3{0.0})
    p.airspeed = formation.airspeed;
  else
    p.airspeed = std::max(p.airspeed - formation.fall_back, s.min_speed);
  const dvec3 d = formation.heading != dvec3{0.0}
                      ? s.w_separation * separation +
                            s.w_formation * (formation.heading +
                                             kFormationRouteHeight * dvec3{0.0, route.y, 0.0})
                      : s.w_route * route + s.w_separation * separation +
                            s.w_alignment * unit_or_zero(heading_sum) +
                            s.w_cohesion * unit_or_zero(cohesion_sum);
  p.direction = unit_or_zero(d);
  return p;
}

BeatPlaces beat_places(const Species& s, const BirdState& b, double shift) {
  BeatPlaces places;
  for (uint32_t k = 0; k < kBeatSamples; ++k) {
    const double beat = 2.0 * kPi * double(k) / double(kBeatSamples);  // of its own wingbeat
    dvec3 right[2];
    right_wing_places(s, b.phase + shift + beat, b.amplitude, b.sweep, right);
    for (int q = 0; q < 2; ++q) {
      places.at[k][q] = right[q];
      places.at[k][2 + q] = dvec3{right[q].x, right[q].y, -right[q].z};  // mirror_to_left's
    }
  }
  return places;
}

void upwash_met_at(const Species& s, const BirdState& b, const Perception& p, const dvec3& up,
                   const BeatPlaces& places, uint32_t lead, std::span<const dvec3> offsets,
                   uint32_t square_to, std::span<double> met) {
  std::fill(met.begin(), met.end(), 0.0);
  if (!(b.frequency > 0.0) || offsets.empty()) return;
  const glm::dmat3 to_world = glm::mat3_cast(b.attitude);
  for (uint32_t k = 0; k < kBeatSamples; ++k) {
    const double beat = 2.0 * kPi * double(k) / double(kBeatSamples);  // of its own wingbeat
    const dvec3(&at)[4] = places.at[(k + lead) % kBeatSamples];
    auto now = [&](uint32_t m) {
      WakeSource w = p.wake[m];
      w.phase += beat * w.frequency / b.frequency;  // the same time on, at its own frequency
      return w;
    };
    // The wake square_to: one pair of vortices serves every place.
    if (p.wakes > 0) {
      const WakeSource w = now(square_to);
      for (const dvec3& point : at) {
        const dvec3 station = b.position + offsets[0] + to_world * point;
        const VortexPair pair = vortex_pair(s, w, station);
        for (size_t o = 0; o < offsets.size(); ++o)
          met[o] += glm::dot(pair_velocity(pair, station + (offsets[o] - offsets[0])), up);
      }
    }
    // The others: a pair for each place.
    for (uint32_t m = 1; m < p.wakes; ++m) {
      const WakeSource w = now(m == square_to ? 0 : m);
      for (const dvec3& point : at) {
        const dvec3 station = b.position + offsets[0] + to_world * point;
        for (size_t o = 0; o < offsets.size(); ++o)
          met[o] += glm::dot(wake_velocity(s, w, station + (offsets[o] - offsets[0])), up);
      }
    }
  }
  for (double& m : met) m /= 4.0 * kBeatSamples;
}

double upwash_met(const Species& s, const BirdState& b, const Perception& p, const dvec3& up,
                  const dvec3& offset, double shift) {
  double met = 0.0;
  upwash_met_at(s, b, p, up, beat_places(s, b, shift), 0, std::span<const dvec3>(&offset, 1), 0,
                std::span<double>(&met, 1));
  return met;
}

namespace {
// Where a parabola through (-step, below), (0, here), (step, above) peaks, within `most` of 0; its
// rising side's end at `most` where it has no peak.
double parabola_peak(double below, double here, double above, double step, double most) {
  const double slope = 0.5 * (above - below), curvature = above - 2.0 * here + below;
  if (curvature < 0.0) return std::clamp(-slope / curvature * step, -most, most);
  return slope > 0.0 ? most : slope < 0.0 ? -most : 0.0;
}
}  // namespace

Formation formation(const Species& s, const BirdState& b, const dvec3& wind, const Perception& p) {
  Formation f;
  if (s.w_formation <= 0.0) return f;
  // It flies in formation on the nearest bird whose wake it meets at least kFormationBehind spans
  // ahead of it. One nearer abreast it drops back from, to where the upwash is better (a wake's
  // upwash grows behind the bird that sheds it): two birds abreast, each a little ahead of the
  // other by turns, would otherwise follow each other and neither fly the route, and birds abreast
  // behind one leader would crowd the same place.
  const WakeSource *leader = nullptr, *abreast = nullptr;
  for (uint32_t m = 0; m < p.wakes; ++m) {
    const double speed = glm::length(p.wake[m].air_velocity);
    if (!(speed > 0.0)) continue;
    const double ahead_by =
        glm::dot(p.wake[m].position - b.position, p.wake[m].air_velocity) / speed;
    if (ahead_by < kFormationBehind * s.box_c) {
      if (!abreast) abreast = &p.wake[m];
    } else if (!leader) {
      leader = &p.wake[m];
    }
  }
  if (!leader && !abreast) return f;
  const WakeSource& lead = leader ? *leader : *abreast;
  const uint32_t lead_index = static_cast<uint32_t>(&lead - p.wake);
  const double speed = glm::length(lead.air_velocity);
  const dvec3 ahead = lead.air_velocity / speed;
  // Across the flight: `side` level, `up` the vertical's part square to the flight.
  dvec3 side = glm::cross(ahead, dvec3{0.0, 1.0, 0.0});
  if (glm::length(side) < 1e-6) return f;
  side = glm::normalize(side);
  const dvec3 up = glm::cross(side, ahead);
  // The bird's wing places over its beat, for every probe: a phase probe's are theirs
  // kPhaseProbeSamples moments on or back.
  const BeatPlaces own = beat_places(s, b, 0.0);
  auto met = [&](const dvec3& offset, uint32_t lead) {
    double upwash = 0.0;
    upwash_met_at(s, b, p, up, own, lead, std::span<const dvec3>(&offset, 1), 0,
                  std::span<double>(&upwash, 1));
    return upwash;
  };
  const double step = kFormationProbe * s.box_c, most = kFormationReach * s.box_c;
  // Here and a step to either side and above and below, square to the flight of the bird ahead:
  // they meet its wake at the same stations behind it (upwash_met_at).
  const dvec3 places[5] = {dvec3{0.0}, -step * side, step * side, -step * up, step * up};
  double around[5];
  upwash_met_at(s, b, p, up, own, 0, std::span<const dvec3>(places, leader ? 5 : 1), lead_index,
                std::span<double>(around, leader ? 5 : 1));
  const double here = around[0];
  const dvec3 across_air = (b.velocity - wind) - lead.air_velocity;
  if (abreast) {
    const double back =
        parabola_peak(met(step * ahead, 0), here, met(-step * ahead, 0), step, most);
    f.fall_back = std::max(back, 0.0) / s.formation_time;
  }
  if (!leader) return f;
  const double across = parabola_peak(around[1], here, around[2], step, most);
  const double above = parabola_peak(around[3], here, around[4], step, most);
  static_assert(kPhaseProbe * kBeatSamples == 2.0 * kPi * kPhaseProbeSamples,
                "kPhaseProbe is kPhaseProbeSamples of the beat's moments");
  const double shift = parabola_peak(met(dvec3{0.0}, kBeatSamples - kPhaseProbeSamples), here,
                                     met(dvec3{0.0}, kPhaseProbeSamples), kPhaseProbe, kPhaseReach);
  // Closing on that place over formation_time: across the flight less how fast it already moves
  // there; up and down by the offset alone. Two birds' vertical velocities at an instant differ
  // mostly by their wingbeats' heave, about opposite at the wingtip path's phase: fed back, that
  // swung the follower's climb at its wingbeat rate, and the swings grew down a chain.
  const double closing_side = across / s.formation_time - glm::dot(across_air, side);
  const double closing_up = above / s.formation_time;
  f.heading = glm::normalize(ahead + (side * closing_side + up * closing_up) / speed);
  // Along the flight it keeps separation_radius from its leader: it flies as far behind it as that
  // leaves at its offset across. (social_goal's law, by the distance along the flight alone, would
  // leave a bird abreast where it is: a line abreast, not a V.) It closes about its species'
  // cruise_speed, not its leader's airspeed and their difference: read at an instant, those carry
  // both birds' wingbeat surges, and a chain in which each copies the one ahead amplifies any swing
  // down the chain (string instability); by the offset alone a follower damps it.
  const dvec3 offset = lead.position - b.position;
  const double behind = glm::dot(offset, ahead);
  const double across2 = std::max(glm::dot(offset, offset) - behind * behind, 0.0);
  const double keep = std::sqrt(std::max(s.separation_radius * s.separation_radius - across2, 0.0));
  f.airspeed = std::clamp(s.cruise_speed + s.speed_gain * (behind - keep) - f.fall_back,
                          s.min_speed, s.max_speed);
  f.phase_rate = shift / s.formation_time;
  return f;
}

std::vector<bool> flocking_species(size_t species, const std::vector<BirdState>& birds) {
  std::vector<bool> flocks(species, false);
  for (const BirdState& b : birds)
    if (b.flocking != 0 && b.species < species) flocks[b.species] = true;
  return flocks;
}

GridShape grid_shape(const std::vector<Species>& species, const std::vector<BirdState>& birds) {
  const std::vector<bool> flocks = flocking_species(species.size(), birds);
  double separation = kMaxGridCell, perception = 0.0;
  for (size_t k = 0; k < species.size(); ++k)
    if (flocks[k]) {
      separation = std::min(separation, species[k].separation_radius);
      perception = std::max(perception, species[k].perception_radius);
    }
  GridShape g;
  const double least = perception / 12.0;
  g.cell = std::exp2(std::round(std::log2(std::max(0.6 * separation, least))));
  // Never below a twelfth of the perception: a bird alone searches at most 12 rings. Rounded down
  // to 16 (the migrants', 1.2-span separation), a lone goose's search outran lavapipe's budget of
  // loop turns (issue 43).
  if (g.cell < least) g.cell *= 2.0;
  g.cell = std::clamp(g.cell, kMinGridCell, kMaxGridCell);
  g.buckets = grid_buckets(birds.size());
  return g;
}

uint32_t SearchReach::total() const {
  uint32_t sum = 0;
  for (const uint32_t c : count) sum += c;
  return sum;
}

void SearchReach::add(const SearchReach& other) {
  for (uint32_t b = 0; b < kReachBins; ++b) count[b] += other.count[b];
}

uint32_t reach_bin(double distance) {
  const double half_octaves = std::floor(2.0 * std::log2(std::max(distance, 1.0)));
  return static_cast<uint32_t>(
      std::clamp(half_octaves - double(kReachFirstBin), 0.0, double(kReachBins - 1)));
}

std::vector<double> grid_cells_allowed(const std::vector<Species>& species,
                                       const std::vector<BirdState>& birds) {
  const std::vector<bool> flocks = flocking_species(species.size(), birds);
  double perception = 0.0;
  for (size_t k = 0; k < species.size(); ++k)
    if (flocks[k]) perception = std::max(perception, species[k].perception_radius);
  // grid_shape's own cell among them (a perception shorter than its separation's cell).
  const double most = std::max(perception, grid_shape(species, birds).cell);
  std::vector<double> cells;
  const double least = std::max(kMinGridCell, std::exp2(std::ceil(std::log2(perception / 12.0))));
  for (double cell = least; cell <= kMaxGridCell; cell *= 2.0) {
    cells.push_back(cell);
    if (cell >= most) break;
  }
  return cells;
}

double grid_cell_for(const SearchReach& reach, const std::vector<double>& allowed) {
  if (reach.total() == 0 || allowed.empty()) return 0.0;
  double best = allowed.front(), least_cost = INFINITY;
  for (const double cell : allowed) {
    double cost = 0.0;
    for (uint32_t b = 0; b < kReachBins; ++b) {
      if (reach.count[b] == 0) continue;
      // The bin's middle, in cm.
      const double r = std::exp2((double(b + kReachFirstBin) + 0.5) / 2.0);
      cost += reach.count[b] * (std::pow(r / cell + 1.0, 3.0) + std::pow(1.0 + cell / r, 3.0));
    }
    if (cost < least_cost) least_cost = cost, best = cell;
  }
  return best;
}

uint32_t grid_buckets(size_t birds) {
  return std::bit_ceil(static_cast<uint32_t>(std::clamp<size_t>(4 * birds, 1024, size_t{1} << 31)));
}

std::vector<glm::ivec4> grid_search_order(const GridShape& shape, double radius, int parts) {
  // The cells that any point of the bird's cell may see, the same for each part.
  const int rings = static_cast<int>(std::ceil(radius / shape.cell));
  std::vector<glm::ivec3> around;
  for (int dz = -rings; dz <= rings; ++dz)
    for (int dy = -rings; dy <= rings; ++dy)
      for (int dx = -rings; dx <= rings; ++dx) {
        const glm::ivec3 gap = glm::max(glm::abs(glm::ivec3(dx, dy, dz)) - 1, 0);
        if ((gap.x * gap.x + gap.y * gap.y + gap.z * gap.z) * shape.cell * shape.cell <=
            radius * radius)
          around.push_back({dx, dy, dz});
      }
  // Nearest first, then ring by ring: the order never depends on the sort's whims.
  auto ring = [](const glm::ivec4& c) {
    return std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z)});
  };
  auto before = [&](const glm::ivec4& a, const glm::ivec4& b) {
    return std::tuple(a.w, ring(a), a.z, a.y, a.x) < std::tuple(b.w, ring(b), b.z, b.y, b.x);
  };
  std::vector<glm::ivec4> order;
  order.reserve(size_t(parts) * parts * parts * around.size());
  for (int part = 0; part < parts * parts * parts; ++part) {
    // In units of a part: the part [p, p + 1) of the bird's cell [0, parts), cell d [parts d, parts
    // d + parts).
    const glm::ivec3 p(part % parts, part / parts % parts, part / (parts * parts));
    const size_t first = order.size();
    for (const glm::ivec3& d : around) {
      const glm::ivec3 gap = glm::max(glm::max(parts * d - (p + 1), p - (parts * d + parts)), 0);
      order.push_back({d, gap.x * gap.x + gap.y * gap.y + gap.z * gap.z});
    }
    std::sort(order.begin() + first, order.end(), before);
  }
  return order;
}

glm::ivec3 grid_cell(const dvec3& position, double cell) {
  return glm::ivec3(glm::floor(position / cell));
}

uint32_t grid_bucket(const glm::ivec3& c, uint32_t buckets) {
  const uint32_t h = static_cast<uint32_t>(c.x) * 73856093u ^
                     static_cast<uint32_t>(c.y) * 19349663u ^
                     static_cast<uint32_t>(c.z) * 83492791u;
  return h & (buckets - 1u);
}

NeighbourGrid::NeighbourGrid(const std::vector<BirdState>& birds, GridShape shape)
    : birds_(birds), shape_(shape), start_(shape.buckets + 1, 0) {
  // Counting sort: a histogram of the buckets, its exclusive prefix sum, a scatter.
  std::vector<uint32_t> bucket(birds.size(), shape.buckets);
  for (size_t i = 0; i < birds.size(); ++i)
    if (flocks_now(birds[i])) {
      bucket[i] = grid_bucket(grid_cell(birds[i].position, shape.cell), shape.buckets);
      ++start_[bucket[i] + 1];
    }
  for (uint32_t k = 0; k < shape.buckets; ++k) start_[k + 1] += start_[k];
  sorted_.resize(start_[shape.buckets]);
  std::vector<uint32_t> next(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < birds.size(); ++i)
    if (bucket[i] < shape.buckets) sorted_[next[bucket[i]]++] = static_cast<uint32_t>(i);
}

std::vector<uint32_t> NeighbourGrid::seen_by(uint32_t i, const std::vector<Species>& species,
                                             const dvec3& wind) const {
  const BirdState& b = birds_[i];
  const Species& s = species[b.species];
  Nearest nearest{static_cast<uint32_t>(s.neighbours), {}, {}};
  if (!flocks_now(b) || s.neighbours < 1.0) return {};
  const dvec3 ahead = flight_direction(b, wind);
  const double cell = shape_.cell;
  const glm::ivec3 home = grid_cell(b.position, cell);
  const int rings = static_cast<int>(std::ceil(s.perception_radius / cell));
  // How far the bird is from its own cell's nearest face.
  const dvec3 low_home = dvec3(home) * cell;
  const dvec3 inside = glm::min(b.position - low_home, low_home + cell - b.position);
  const double edge = std::max(0.0, std::min({inside.x, inside.y, inside.z}));
  for (int r = 0; r <= rings; ++r) {
    // Every cell of ring r is at least r - 1 cells and `edge` away: stop once none can hold a
    // nearer bird, nor one as near of a lower index (ties go by index: a cell exactly at the k-th's
    // distance may hold one; cells of 10 m on a lattice of 2.56 m had one).
    const double inner = (r - 1) * cell + edge;
    if (r > 0 && nearest.full() && inner * inner > nearest.worst2()) break;
    for (int dx = -r; dx <= r; ++dx)
      for (int dy = -r; dy <= r; ++dy) {
        const bool side = std::abs(dx) == r || std::abs(dy) == r;
        for (int dz = -r; dz <= r; dz += side ? 1 : std::max(2 * r, 1)) {
          const glm::ivec3 c = home + glm::ivec3(dx, dy, dz);
          // The gap from the bird to the cell's box: skip a cell that cannot hold a nearer bird.
          const dvec3 low = dvec3(c) * cell, high = low + cell;
          const dvec3 gap = glm::max(glm::max(low - b.position, b.position - high), dvec3{0.0});
          const double gap2 = glm::dot(gap, gap);
          if (gap2 > s.perception_radius * s.perception_radius ||
              (nearest.full() && gap2 > nearest.worst2()))
            continue;
          const uint32_t k = grid_bucket(c, shape_.buckets);
          for (uint32_t e = start_[k]; e < start_[k + 1]; ++e) {
            const uint32_t j = sorted_[e];
            // Only the birds of this very cell, not of another hashed into the same bucket: each
            // bird is met once.
            if (grid_cell(birds_[j].position, cell) == c) consider(nearest, s, birds_, i, j, ahead);
          }
        }
      }
  }
  return nearest.index;
}

std::vector<uint32_t> seen_by_brute_force(uint32_t i, const std::vector<BirdState>& birds,
                                          const std::vector<Species>& species, const dvec3& wind) {
  const Species& s = species[birds[i].species];
  Nearest nearest{static_cast<uint32_t>(s.neighbours), {}, {}};
  if (!flocks_now(birds[i]) || s.neighbours < 1.0) return {};
  const dvec3 ahead = flight_direction(birds[i], wind);
  for (uint32_t j = 0; j < birds.size(); ++j) consider(nearest, s, birds, i, j, ahead);
  return nearest.index;
}

namespace {
// The wakes bird b meets (Perception::wake): of the birds it sees, nearest first, those ahead of
// it within kWakeReach of its spans.
void see_wakes(const Species& s, const BirdState& b, const dvec3& wind,
               std::span<const uint32_t> seen, const std::vector<BirdState>& birds,
               const World& world, uint64_t step, Perception& p) {
  const dvec3 ahead = flight_direction(b, wind);
  p.wake_step = static_cast<uint32_t>(step);
  for (const uint32_t j : seen) {
    if (p.wakes == kWakeSources) break;
    const BirdState& o = birds[j];
    const dvec3 offset = o.position - b.position;
    if (glm::dot(offset, ahead) <= 0.0 || glm::length(offset) > kWakeReach * s.box_c) continue;
    WakeSource& w = p.wake[p.wakes++];
    w.position = o.position;
    w.air_velocity = o.velocity - wind_at(world, o.position.y);
    w.attitude = o.attitude;
    w.lift = o.lift;
    w.phase = o.phase;
    w.frequency = o.frequency;
    w.amplitude = o.amplitude;
  }
}

// What bird `i` of `birds` perceives now, from `grid`; its seen_key by `ids` where given.
// `reached`, where given: how far its search reached (SearchReach).
Perception perceive_one(const NeighbourGrid& grid, const std::vector<BirdState>& birds, uint32_t i,
                        const std::vector<Species>& species, const World& world, uint64_t step,
                        std::span<const uint32_t> ids = {}, double* reached = nullptr) {
  const BirdState& b = birds[i];
  const Species& s = species[b.species];
  const dvec3 wind = wind_at(world, b.position.y);  // the air it flies in
  const std::vector<uint32_t> seen = grid.seen_by(i, species, wind);
  if (reached)
    *reached = seen.empty() || seen.size() < static_cast<size_t>(s.neighbours)
                   ? s.perception_radius
                   : glm::length(birds[seen.back()].position - b.position);
  BirdState route_bird = b;  // route_goal passes targets: the step does that, not the eyes
  dvec3 goal = seen.empty() ? dvec3{0.0} : route_goal(route_bird, s, world);
  bool route_done = route_over(route_bird, world);
  if (const std::optional<dvec3> on = onward_goal(route_bird, world))
    goal = *on, route_done = false;
  Perception wakes;
  if (b.flocking & kFeelsWakes) see_wakes(s, b, wind, seen, birds, world, step, wakes);
  const Formation f = formation(s, b, wind, wakes);
  Perception p = social_goal(s, b, wind, goal, route_done, seen, birds, f);
  p.wakes = wakes.wakes;
  p.wake_step = wakes.wake_step;
  std::copy(std::begin(wakes.wake), std::end(wakes.wake), std::begin(p.wake));
  p.phase_rate = f.phase_rate;
  if (!ids.empty()) {
    p.seen_key = 0;
    for (const uint32_t j : seen) p.seen_key += ids[j] * kSeenKeyFactor;
  }
  return p;
}
}  // namespace

void perceive(const std::vector<BirdState>& birds, const std::vector<Species>& species,
              const World& world, uint64_t frame, uint64_t step, double frame_seconds,
              GridShape shape, std::vector<Perception>& perception, SearchReach* reach) {
  perception.resize(birds.size());
  const NeighbourGrid grid(birds, shape);
  const int64_t n = static_cast<int64_t>(birds.size());
#pragma omp parallel
  {
    SearchReach mine;
#pragma omp for schedule(dynamic, 256)
    for (int64_t i = 0; i < n; ++i) {
      const BirdState& b = birds[static_cast<size_t>(i)];
      const Species& s = species[b.species];
      if (frame % reaction_frames(s, frame_seconds) != 0) continue;
      double reached = 0.0;
      perception[static_cast<size_t>(i)] =
          perceive_one(grid, birds, static_cast<uint32_t>(i), species, world, step, {}, &reached);
      if (flocks_now(b) && s.neighbours >= 1.0) ++mine.count[reach_bin(reached)];
    }
    if (reach) {
#pragma omp critical
      reach->add(mine);
    }
  }
}

void perceive(const std::vector<BirdState>& birds, std::span<const uint32_t> ids,
              std::span<const uint32_t> perceivers, const std::vector<Species>& species,
              const World& world, uint64_t frame, uint64_t step, double frame_seconds,
              GridShape shape, std::vector<Perception>& perception) {
  perception.resize(perceivers.size());
  const NeighbourGrid grid(birds, shape);
  const int64_t n = static_cast<int64_t>(perceivers.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (int64_t k = 0; k < n; ++k) {
    const uint32_t i = perceivers[static_cast<size_t>(k)];
    if (frame % reaction_frames(species[birds[i].species], frame_seconds) != 0) continue;
    perception[static_cast<size_t>(k)] = perceive_one(grid, birds, i, species, world, step, ids);
  }
}

WakeSource wake_now(const WakeSource& seen, uint32_t seen_step, uint64_t step, double dt,
                    const dvec3& wind) {
  const double since = double(static_cast<uint32_t>(step) - seen_step) * dt;  // mod 2^32 steps
  WakeSource w = seen;
  w.position += (seen.air_velocity + wind) * since;
  w.phase = seen.phase + 2.0 * kPi * seen.frequency * since;
  return w;
}

}  // namespace aeroflock
