#include "world.h"

#include <cmath>

#include "constants.h"

namespace aeroflock {

glm::dvec3 target_position(const Target& t, double time) {
  glm::dvec3 p = t.centre + t.velocity * time;
  if (t.period > 0.0) p += t.amplitude * std::sin(2.0 * kPi * time / t.period);
  return p;
}

glm::dvec3 wind_at(const World& w, double y) {
  const double h = y - w.ground_height;
  switch (w.wind_profile) {
    case WindProfile::uniform:
      return w.wind;
    case WindProfile::power_law:
      return h > 0.0 ? w.wind * std::pow(h / w.wind_height, w.wind_exponent) : glm::dvec3(0.0);
    case WindProfile::logarithmic:
      return h > w.wind_roughness ? w.wind * (std::log(h / w.wind_roughness) /
                                              std::log(w.wind_height / w.wind_roughness))
                                  : glm::dvec3(0.0);
  }
  return w.wind;
}

void World::move_targets(double time) {
  target_now.resize(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) target_now[i] = target_position(targets[i], time);
}

}  // namespace aeroflock
