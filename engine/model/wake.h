// The wake a flapping bird leaves in the air (issue 43; docs/MODEL.md "The wake"): a pair of
// trailing tip vortices whose circulation follows from its lift (lifting line), lying behind it
// along its flight through the air and displaced with its wingtips at the phase they had when they
// shed that part of the wake, so that a flapping wake is wavy with no history stored. A neighbour
// behind meets the velocity they induce: downwash behind the bird, upwash outboard of its wings.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "species.h"

namespace aeroflock {

// What a bird's wake follows from: its state when it was seen.
struct WakeSource {
  glm::dvec3 position{0.0};                 // its centre, cm
  glm::dvec3 air_velocity{0.0};             // its velocity through the air, cm/s
  glm::dquat attitude{1.0, 0.0, 0.0, 0.0};  // body to world
  double lift = 0.0;                        // its wings' lift, dyn
  double phase = 0.0;                       // wingbeat phase psi now, rad
  double frequency = 0.0;                   // Hz
  double amplitude = 0.0;                   // amp
};

// Elliptic loading rolls the trailing vorticity up into two vortices pi / 4 of the span apart
// (Prandtl's lifting line; Lissaman and Shollenberg 1970, Hummel 1983): the vortex span b' of a
// bird of span box_c.
double vortex_span(const Species& s);

// The circulation of the tip vortices, cm^2/s: lift = density x airspeed x circulation x vortex
// span (Kutta-Joukowski over the lifting line). 0 without airspeed.
double wake_circulation(const Species& s, double lift, double airspeed);

// The radius of the vortices' cores, cm: kWakeCore of the span. Inside it the swirl falls to 0
// at the axis (a Burnham-Hallock core, v = circulation / 2 pi x r / (r^2 + core^2)), so that
// nothing diverges.
double wake_core(const Species& s);

// Where a tip vortex lies across the flight, a streamwise `distance` (cm, >= 0) behind the bird:
// the wingtip (right_wingtip) at the phase it had when it shed that part of the wake, `distance` /
// airspeed ago, scaled by pi / 4 about the body's long axis, body frame (x unused: 0). The right
// one's; the left one is its mirror (z negated).
glm::dvec3 vortex_place(const Species& s, const WakeSource& src, double distance);

// The velocity (cm/s, world) that the wake of `src`, a bird of species `s`, induces at `point`:
// both tip vortices as straight lines from the bird's station backwards along its flight through
// the air, each through its place (vortex_place) at the point's own station behind the bird.
glm::dvec3 wake_velocity(const Species& s, const WakeSource& src, const glm::dvec3& point);

// wake_velocity in two halves, for several points at one station behind the bird (formation
// flying's probes across the flight share their station): the two vortex lines there, then the
// velocity they induce at a point.
struct VortexPair {
  glm::dvec3 right_start{0.0}, left_start{0.0};  // where the lines pass the station, cm
  glm::dvec3 back{0.0};                          // the wake's way, unit (0: no wake)
  double circulation = 0.0, core = 0.0;          // the right line's, cm^2/s; cm
};
VortexPair vortex_pair(const Species& s, const WakeSource& src, const glm::dvec3& station);
glm::dvec3 pair_velocity(const VortexPair& pair, const glm::dvec3& point);

}  // namespace aeroflock
