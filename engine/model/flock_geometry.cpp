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
    if (is_finite(b)) e.centre += b.position, e.mean_velocity += b.velocity, ++e.finite;
  if (e.finite == 0) return e;
  e.centre /= double(e.finite);
  e.mean_velocity /= double(e.finite);
  double spread = 0.0;
  for (const BirdState& b : birds)
    if (is_finite(b)) {
      const double d = glm::distance(b.position, e.centre);
      e.radius = std::max(e.radius, d);
      spread += d * d;
    }
  e.rms_radius = std::sqrt(spread / double(e.finite));
  return e;
}

}  // namespace aeroflock
