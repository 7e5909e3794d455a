// What the birds fly through: targets, routes, branches and the ground (paper 3.4, 4.2-4.4).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace aeroflock {

// A target sphere; its centre moves as centre + velocity t + amplitude sin(2 pi t / period).
struct Target {
  std::string name;
  glm::dvec3 centre{0.0};
  double radius = 200.0;      // cm
  glm::dvec3 velocity{0.0};   // cm/s
  glm::dvec3 amplitude{0.0};  // cm
  double period = 0.0;        // s (0: no oscillation)
};
glm::dvec3 target_position(const Target& t, double time);

// A branch: a horizontal perch. The bird lands on `point`; the branch runs along `direction`.
struct Branch {
  std::string name;
  glm::dvec3 point{0.0};
  glm::dvec3 direction{1.0, 0.0, 0.0};  // unit, horizontal
  double length = 100.0;                // cm, for drawing
};

// A route: targets passed in order, optionally looping, optionally ending on a branch.
struct Route {
  std::string name;
  std::vector<uint32_t> targets;  // indices into World::targets
  bool loop = false;
  int32_t branch = -1;       // index into World::branches to land on at the end, -1: none
  bool path_control = true;  // landing through the Bezier point P (paper 4.4)
};

enum class TurningModel : uint32_t { tail = 0, fixed_rate = 1 };

// How the wind grows with height h above the ground: uniform (the same everywhere), a power law
// (h / h_ref)^alpha, or logarithmic ln(h / z0) / ln(h_ref / z0) (none below z0); the wind is
// World::wind at h_ref = wind_height.
enum class WindProfile : uint32_t { uniform = 0, power_law = 1, logarithmic = 2 };

struct World {
  std::vector<Target> targets;
  std::vector<Route> routes;
  std::vector<Branch> branches;
  double ground_height = 0.0;  // cm
  bool ground_effect = true;   // eq. 15 on or off
  TurningModel turning = TurningModel::tail;
  glm::dvec3 wind{0.0};  // cm/s, at wind_height (every height: uniform)
  WindProfile wind_profile = WindProfile::uniform;
  double wind_height = 1000.0;       // h_ref, cm above the ground
  double wind_exponent = 1.0 / 7.0;  // alpha of the power law (open country)
  double wind_roughness = 3.0;       // z0 of the logarithmic profile, cm (short grass)
  // Where each target is now: the host moves targets between frames.
  std::vector<glm::dvec3> target_now;
  void move_targets(double time);
};

// The wind at world height y (cm).
glm::dvec3 wind_at(const World& w, double y);

}  // namespace aeroflock
