// Where the flock is, from the birds whose state is finite: a bird whose state has blown up (NaN
// or infinity) is left out rather than spoiling the figures of the rest.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

#include "model/bird.h"

namespace aeroflock {

// Whether the bird's position, velocity and attitude are all finite.
bool is_finite(const BirdState& bird);

struct FlockExtent {
  glm::dvec3 centre{0.0};         // mean position of the finite birds, cm (0 when there are none)
  glm::dvec3 mean_velocity{0.0};  // cm/s
  double radius = 0.0;            // largest distance of a finite bird from the centre, cm
  double rms_radius = 0.0;        // root mean square distance from the centre, cm
  size_t finite = 0;              // how many birds are finite
};

FlockExtent flock_extent(const std::vector<BirdState>& birds);

}  // namespace aeroflock
