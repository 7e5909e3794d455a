// Flocking (docs/MODEL.md "Flocking", beyond the paper): what a bird sees of its flock, once per
// reaction time, and the social goal it then steers for through the paper's controller. No social
// force acts on a body.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "bird.h"
#include "constants.h"
#include "species.h"
#include "wake.h"
#include "world.h"

namespace aeroflock {

// What a bird's perception leaves for the steps that follow it (GpuPerception on the device).
struct Perception {
  glm::dvec3 direction{0.0};  // u(d): the social goal's direction, world; 0 when it sees no one
  double airspeed = 0.0;      // the airspeed it commands, cm/s (0: none)
  uint32_t neighbours = 0;    // how many birds it sees (at most the species' `neighbours`)
  double nearest = 0.0;       // cm to the nearest of them (0: none)
  uint32_t seen_key = 0;      // sum of the seen birds' indices times kSeenKeyFactor (mod 2^32): a
                              // checksum by which the tests compare neighbour sets across backends
  // A bird that meets wakes (kFeelsWakes): those of the nearest it sees ahead of it within
  // kWakeReach spans, nearest first, as they were at step `wake_step` (its low 32 bits); the steps
  // after it advance them (wake_now).
  uint32_t wakes = 0;
  uint32_t wake_step = 0;
  WakeSource wake[kWakeSources]{};
  // Formation flying (w_formation > 0): how much faster than its frequency its wingbeat's phase
  // runs until the next perception, rad/s, to meet the wakes' upwash best (formation()).
  double phase_rate = 0.0;
};

// Formation flying (issue 43; docs/MODEL.md "Formation flying"): what a bird that meets the wakes
// `p.wake` seeks. It predicts the upwash its wings would meet over one of its wingbeats
// (upwash_met) a little to either side of where it is, above and below, and with its wingbeat a
// little ahead and behind, and takes the best of each from a parabola through the three: no place
// and no phase is prescribed, both come from the wakes. `heading`: through the air, unit, along
// the nearest wake's bird, turned to close on that place over formation_time as the bird moves
// across relative to it; `phase_rate` to close on that phase.
struct Formation {
  glm::dvec3 heading{0.0};
  double airspeed = 0.0;  // cm/s: its cruise_speed, faster or slower to keep separation_radius
                          // from its leader (as social_goal's airspeed does from the flock)
  double phase_rate = 0.0;
  double fall_back = 0.0;  // cm/s slower than the flock's airspeed: nearly abreast of the bird
                           // ahead, it drops back into that bird's wake
};
Formation formation(const Species& s, const BirdState& b, const glm::dvec3& wind,
                    const Perception& p);

// The upwash (cm/s) that bird b's wings meet from the wakes `p.wake` (as seen now), on average
// over its four wing points and one of its wingbeats, were it `offset` (cm) from where it is and
// its wingbeat `shift` (rad) ahead of its own: the wakes' air along `up` (across its flight).
// Over the beat both birds keep their places; their wingbeats run on at their frequencies.
double upwash_met(const Species& s, const BirdState& b, const Perception& p, const glm::dvec3& up,
                  const glm::dvec3& offset, double shift);

// Bird b's four wing points (body frame: right arm, right hand, left arm, left hand) at the
// kBeatSamples moments of one of its wingbeats that upwash_met samples, its wingbeat `shift` (rad)
// ahead of its own.
struct BeatPlaces {
  glm::dvec3 at[kBeatSamples][4];
};
BeatPlaces beat_places(const Species& s, const BirdState& b, double shift);

// upwash_met at each of `offsets` at once (into `met`, as many), the bird's wings at `places`
// `lead` moments on (its wingbeat lead x 2 pi / kBeatSamples ahead of theirs). Where the offsets
// differ from the first only square to the flight of the bird whose wake is `p.wake[square_to]`
// (formation's probes across the flight of the bird ahead), they meet that wake at the first's
// stations behind it: its vortices' places and strength there serve them all (the most of the
// cost). `square_to` < p.wakes, or 0 where there is one offset.
void upwash_met_at(const Species& s, const BirdState& b, const Perception& p, const glm::dvec3& up,
                   const BeatPlaces& places, uint32_t lead, std::span<const glm::dvec3> offsets,
                   uint32_t square_to, std::span<double> met);

// A wake source seen at step `seen_step` (low 32 bits) as it is at step `step`, `dt` apart: moved
// by its velocity over the ground (its air velocity and the `wind`), its wingbeat advanced by its
// frequency.
WakeSource wake_now(const WakeSource& seen, uint32_t seen_step, uint64_t step, double dt,
                    const glm::dvec3& wind);

// Whether a bird takes part in its flock now: its flock flocks and it flies (not standing, taking
// off, landing or perched, nor on its way to a branch). Only such birds see and are seen.
bool flocks_now(const BirdState& b);

// Whether a bird flying along `ahead` (unit: through the air, where its head points) sees one at
// `offset` (cm) from it, one its k nearest are chosen from: within perception_radius and outside
// the blind sector (outside_blind); anywhere within that radius for a species whose separation
// heeds all round (separation_all_round), its blind sector then hiding a bird from the rest of its
// social goal alone (social_goal).
bool sees(const Species& s, const glm::dvec3& ahead, const glm::dvec3& offset);

// Whether `offset` is outside the blind sector of a bird flying along `ahead`: blind_angle wide,
// centred straight behind it.
bool outside_blind(const Species& s, const glm::dvec3& ahead, const glm::dvec3& offset);

// How often a bird of species `s` perceives: every this many frames (at least 1), from
// reaction_time and the frame's length.
uint32_t reaction_frames(const Species& s, double frame_seconds);

// The route's share of d for a bird `to_goal` (cm) from its route goal: towards the point
// height_capture ahead on the way to it, at the goal's height (the goal itself when nearer). Far
// from the goal, u(to_goal) alone has almost no vertical share: a flock's height was then held so
// weakly that it wandered hundreds of metres off its route's (docs/MODEL.md "Flocking").
glm::dvec3 route_direction(const Species& s, const glm::dvec3& to_goal);

// The route's share of d as a heading through the air: route_direction's level part turned to
// where a bird at `airspeed` (cm/s, its own now) heads in `wind` to make good that track
// (track_aim), as far as it compensates for drift (compensated_aim); its vertical part as it is. A
// flock flies in the air it moves with, so every other share of d is taken in that air: the flock's
// own motion is then the same in any uniform wind as in calm air, and only the route knows the
// ground. Taken over the ground (as before), a crab of 53 degrees in 8 m/s across made each change
// of airspeed a move across the flock, and 100 birds split into two flocks side by side
// (docs/MODEL.md "Flocking").
glm::dvec3 route_heading(const Species& s, const glm::dvec3& to_goal, const glm::dvec3& wind,
                         double airspeed);

// The airspeed (cm/s) by which the cohesion pulls a bird flying along `ahead` (unit) towards
// `cohesion` (unit): cruise_speed w_cohesion (cohesion . ahead) / (w_route + w_alignment +
// w_cohesion). Steering turns the bird across its flight as far as the cohesion tilts u(d); along
// its flight only the airspeed can act, so the pull asks the same of it (docs/MODEL.md
// "Flocking": without it a flock stretches along its flight over hours).
double cohesion_pull(const Species& s, const glm::dvec3& cohesion, const glm::dvec3& ahead);

// How far a neighbour at `offset` (cm) is as the separation zone measures it: its part along the
// flight `ahead` (unit) shrunk by separation_front, so that the zone is a spheroid reaching that
// many times farther ahead and behind than across. A bird sidesteps a neighbour diagonally ahead or
// behind from farther off than one beside it, and its nearest neighbours end at its sides, as a
// starling's are (Ballerini et al. 2008, PNAS; docs/FIELD.md).
double zone_distance(const Species& s, const glm::dvec3& offset, const glm::dvec3& ahead);

// Where a neighbour at `offset` (cm) will be nearest within separation_lookahead seconds, at
// `closing` = its velocity less the bird's (both held): the separation acts there, so that two
// birds closing fast step apart before they meet, not once they are close. The real starling's
// zone, 1.45 m across, leaves a bird closing at 1-5 m/s under a second (docs/FIELD.md). `offset`
// with no lookahead, when they draw apart, or when they would meet or pass (the nearest point not
// on offset's side: a rounding residual's sign says nothing).
glm::dvec3 nearest_offset(const Species& s, const glm::dvec3& offset, const glm::dvec3& closing);

// The social goal from the birds it sees, `seen` (indices into `birds`, nearest first; ties by
// index), for a bird in `wind` (its own: its neighbours are metres away): the desired heading d of
// docs/MODEL.md through that air from separation (the seen birds inside the separation zone,
// zone_distance < separation_radius, fall-off (1 - zone_distance / separation_radius)^2, each
// where nearest_offset puts it),
// alignment (with their air velocities), cohesion (those farther than separation_radius: one
// ahead or behind may be inside the zone and beyond that radius, and count in both) and the route
// (towards `route_goal`: route_heading at the airspeed below), and the airspeed: cruise_speed plus
// speed_gain times how far the seen birds are along its flight from where they would be at
// separation_radius (offset (1 - separation_radius / distance): a bird close ahead slows it, one
// far ahead speeds it up), those nearer than separation_radius each in full, those beyond by their
// mean, plus speed_match times how much faster they fly along its flight, on average (a damper:
// neighbours match speeds before they pass one another), plus the cohesion's pull
// (cohesion_pull); within [min_speed, max_speed].
// `route_done`: its route is over and has no leg to fly on along (route.h: onward_goal): it flies
// on with its flock, without the route's share of d.
// `formation`: a bird flying in formation (its heading not 0) steers by the separation and the
// formation alone, at the formation's airspeed: the bird ahead whose wake it rides flies the route
// for it. A bird of a formation species that sees none of them ahead of it heads the formation: it
// flies the route at its own airspeed (0: none commanded), heeding only the separation.
// A species whose separation heeds all round (separation_all_round, StarDisplay's): the seen birds
// in its blind sector count in the separation alone, not in the alignment, cohesion or airspeed.
Perception social_goal(const Species& s, const BirdState& b, const glm::dvec3& wind,
                       const glm::dvec3& route_goal, bool route_done,
                       std::span<const uint32_t> seen, const std::vector<BirdState>& birds,
                       const Formation& formation = {});

// The uniform grid that finds neighbours (FLAME GPU's spatial messaging): cells of `cell` cm,
// hashed into `buckets` (a power of two) so that memory grows with the birds, not with the world;
// a counting sort puts the birds in bucket order. The compute shaders build the same grid.
struct GridShape {
  double cell = 0.0;     // cm
  uint32_t buckets = 0;  // power of two
};
// The shape for these birds: cells of 0.6 the smallest separation_radius of the species whose
// birds flock (at least a twelfth of their largest perception_radius), to the nearest power of
// two of cm, but not below that twelfth, within [kMinGridCell, kMaxGridCell] (so that a whole
// number of cells fills the device's world tile, gpu/host_device.h, and a cell and a bird's place
// in it are exact there: a bird alone searches at most 12 rings, and grid_search_order lists at
// most about 15,600 cells a part), about four buckets a bird (a power of two, at least 1,024; the
// device's table of cells has at least as many slots, and up to four times as many, its sides
// fitted to the flocks: gpu/grid_table.h). The cell is about the distance to a bird's nearest:
// larger cells hold more birds that are not the nearest, smaller ones cost more cells to search.
// Measured on lavapipe (10,000 starlings of `murmuration`, the ring search): cells of 0.45, 0.6,
// 0.8 and 1 separation_radius cost 2.9, 2.8, 3.2 and 3.7 s for 1.5 s flown. It sets only how fast
// the search is, never what it finds.
inline constexpr double kMinGridCell = 64.0, kMaxGridCell = 16384.0;  // cm
GridShape grid_shape(const std::vector<Species>& species, const std::vector<BirdState>& birds);
// How far the birds' neighbour searches reached (issue 44): of each perceiving bird, the distance
// to the k-th nearest it saw, or its perception_radius where it saw fewer (its search then covered
// all of its sight), counted in half-octave bins (reach_bin). The cell that suits a bird is about
// its reach: a sparse flock's birds (the migrants' skeins, 80 of 96 geese seeing fewer than 7
// within 20 m) search every cell of their sight, some 2,600 of 2.56 m, where cells of 20 m cost 27.
struct SearchReach {
  std::array<uint32_t, kReachBins> count{};
  uint32_t total() const;
  void add(const SearchReach& other);
};
// The bin of a reach of `distance` cm: floor(2 log2(distance)) - kReachFirstBin, within the bins.
uint32_t reach_bin(double distance);
// The cells a grid for these birds may have: the powers of two of cm from grid_shape's least (a
// twelfth of the largest perception_radius, kMinGridCell) to the first at or past that perception
// (kMaxGridCell at most), smallest first.
std::vector<double> grid_cells_allowed(const std::vector<Species>& species,
                                       const std::vector<BirdState>& birds);
// Of `allowed`, the cell whose search costs least for birds that reached `reach`: a bird of reach
// R searches about (R / cell + 1)^3 cells and meets about k (1 + cell / R)^3 birds, alike in cost
// on lavapipe (roofline.md), so that a cell about R suits it. 0 when `reach` counts no bird.
double grid_cell_for(const SearchReach& reach, const std::vector<double>& allowed);

// The buckets of a grid of `birds` birds (grid_shape's).
uint32_t grid_buckets(size_t birds);
// Which of `species` species have birds that flock (the grid's cells and search are theirs).
std::vector<bool> flocking_species(size_t species, const std::vector<BirdState>& birds);
// The cells around a bird's own that a bird in it may see within `radius`, in the order a bird in
// each part of its cell searches them (the cell cut into `parts` along each axis; the lists one
// after the other, x fastest): offsets (xyz) and the least distance between a point of that part
// and one of that cell (w, in parts^2: the distance^2 is w (cell / parts)^2, exact for a power
// of two), nearest first, ties ring by ring. Searching them in this order a bird may stop at the
// first cell whose least distance exceeds its k-th nearest so far (the compute shaders' search,
// flock.glsl): the finer the parts, the sooner.
std::vector<glm::ivec4> grid_search_order(const GridShape& shape, double radius, int parts);
glm::ivec3 grid_cell(const glm::dvec3& position, double cell);
uint32_t grid_bucket(const glm::ivec3& cell, uint32_t buckets);

class NeighbourGrid {
 public:
  // Sorts the birds that flock now (flocks_now) into their buckets.
  NeighbourGrid(const std::vector<BirdState>& birds, GridShape shape);
  // The birds bird `i`, in `wind` (where it flies), sees, at most its species' `neighbours`,
  // nearest first (ties by index): only birds of its own flock that flock now. Searches the cells
  // ring by ring outwards and stops once no unsearched cell can hold a nearer bird.
  std::vector<uint32_t> seen_by(uint32_t i, const std::vector<Species>& species,
                                const glm::dvec3& wind) const;

 private:
  const std::vector<BirdState>& birds_;
  GridShape shape_;
  std::vector<uint32_t> start_;   // first entry of each bucket in `sorted_`, and the end
  std::vector<uint32_t> sorted_;  // bird indices in bucket order
};

// The same by testing every bird: what the grid is tested against.
std::vector<uint32_t> seen_by_brute_force(uint32_t i, const std::vector<BirdState>& birds,
                                          const std::vector<Species>& species,
                                          const glm::dvec3& wind);

// Every bird's perception: due birds (frame a multiple of their reaction_frames) that flock now
// get a new one from the grid, due birds that do not get none, the rest keep theirs.
// `step`: the run's step at the frame's start (the wakes' time). The grid of `shape` (grid_shape's
// or one of grid_cells_allowed: the cell never changes what a bird sees); `reach`, where given,
// gains how far each due bird's search reached.
void perceive(const std::vector<BirdState>& birds, const std::vector<Species>& species,
              const World& world, uint64_t frame, uint64_t step, double frame_seconds,
              GridShape shape, std::vector<Perception>& perception, SearchReach* reach = nullptr);
// The same for the birds `perceivers` of `birds` alone (perception[k] is perceivers[k]'s), on a
// grid of `shape`, each bird's seen_key summed over `ids` (its global id) rather than its index:
// one rank's birds among their ghosts (dist/). `birds` in the order of `ids`, ascending, so
// that ties between equally near birds fall as on one rank.
void perceive(const std::vector<BirdState>& birds, std::span<const uint32_t> ids,
              std::span<const uint32_t> perceivers, const std::vector<Species>& species,
              const World& world, uint64_t frame, uint64_t step, double frame_seconds,
              GridShape shape, std::vector<Perception>& perception);

}  // namespace aeroflock
