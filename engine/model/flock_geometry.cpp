#include "model/flock_geometry.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace aeroflock {
namespace {

bool is_finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

bool is_finite(const BirdState& bird) {
  const glm::dquat& q = bird.attitude;
  return is_finite(bird.position) && is_finite(bird.velocity) && std::isfinite(q.w) &&
         std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}

FlockExtent flock_extent(const std::vector<BirdState>& birds) {
  FlockExtent e;
  for (const BirdState& b : birds)
    if (is_finite(b)) e.centre += b.position, ++e.finite;
  if (e.finite == 0) return e;
  e.centre /= double(e.finite);
  for (const BirdState& b : birds)
    if (is_finite(b)) e.radius = std::max(e.radius, glm::distance(b.position, e.centre));
  return e;
}

}  // namespace aeroflock
