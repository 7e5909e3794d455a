// Where the flock is, from the birds whose state is finite: a bird whose state has blown up (NaN
// or infinity, or quarantined when it did) is left out rather than spoiling the figures of the
// rest.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "model/bird.h"
#include "model/species.h"

namespace aeroflock {

// Whether the bird's position, velocity and attitude are all finite, and it is not quarantined: a
// step that would have left them non-finite froze it at its last finite state (step.cpp), which is
// no longer where it would be. Everything that counts NaN birds counts quarantined ones.
bool is_finite(const BirdState& bird);

struct FlockExtent {
  glm::dvec3 centre{0.0};         // mean position of the finite birds, cm (0 when there are none)
  glm::dvec3 mean_velocity{0.0};  // cm/s
  double radius = 0.0;            // largest distance of a finite bird from the centre, cm
  double rms_radius = 0.0;        // root mean square distance from the centre, cm
  size_t finite = 0;              // how many birds are finite
};

FlockExtent flock_extent(const std::vector<BirdState>& birds);

// The main body of a flock, as a camera frames it: stragglers and a few birds of another flock
// far off do not shrink the picture of the rest.
struct FlockCore {
  glm::dvec3 centre{0.0};    // per-axis median of the finite birds' positions, cm
  double radius = 0.0;       // distance from the centre within which `fraction` of them lie, cm
  glm::dvec3 velocity{0.0};  // mean velocity of the birds within it, cm/s
  size_t finite = 0;
};
// Of the birds of flock `flock` (Flock's index; kAnyFlock: of all of them).
inline constexpr uint32_t kAnyFlock = ~0u;
FlockCore flock_core(const std::vector<BirdState>& birds, double fraction = 0.9,
                     uint32_t flock = kAnyFlock);

// How much a group of birds is a flock (docs/MODEL.md "What a flock must show"), over the finite
// birds given; every distance is to the nearest of them, whatever its direction.
struct FlockMetrics {
  size_t birds = 0;             // finite birds measured
  double median_nearest = 0.0;  // median nearest-neighbour distance, cm (0: fewer than two)
  double too_close = 0.0;  // fraction of them with a neighbour nearer than half a wingspan (box_c)
  double polarisation = 0.0;  // |mean of u(v_i)|, in [0, 1]
  double largest_cluster =
      0.0;  // fraction in the largest cluster, birds linked within cluster_link
};
inline constexpr double kClusterLink = 500.0;  // cm (docs/MODEL.md: 5 m)

// `members`: indices into `birds` (all of them when empty).
FlockMetrics flock_metrics(const std::vector<BirdState>& birds, const std::vector<Species>& species,
                           const std::vector<uint32_t>& members = {});
// Every bird's distance to its nearest finite neighbour among `members` (infinity with none).
std::vector<double> nearest_distances(const std::vector<BirdState>& birds,
                                      const std::vector<uint32_t>& members);

}  // namespace aeroflock
