#include "world.h"

#include <cmath>

#include "constants.h"

namespace aeroflock {

glm::dvec3 target_position(const Target& t, double time) {
  glm::dvec3 p = t.centre + t.velocity * time;
  if (t.period > 0.0) p += t.amplitude * std::sin(2.0 * kPi * time / t.period);
  return p;
}

void World::move_targets(double time) {
  target_now.resize(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) target_now[i] = target_position(targets[i], time);
}

}  // namespace aeroflock
