// Where a bird is going: the targets of its route (paper 3.4) and the landing on a branch (4.4).
#pragma once

#include <optional>

#include <glm/vec3.hpp>

#include "bird.h"
#include "species.h"
#include "world.h"

namespace aeroflock {

// Where the bird sits when perched on `branch`.
glm::dvec3 perch_point(const Species& s, const Branch& branch);

// The way from the bird to where it perches on its route's branch (perch - position, cm), once
// the perch is its goal; none before then (on its way to the landing gate too), or without one.
std::optional<glm::dvec3> way_to_perch(const BirdState& b, const Species& s, const World& w);

// The bird's goal this step: the current target of its route, or the point it steers for on its
// way to the branch. Passes targets and places the landing curve as the bird goes.
glm::dvec3 route_goal(BirdState& b, const Species& s, const World& w);

// Whether the bird has passed the last target of a route that neither loops nor lands: alone, it
// keeps steering for that target.
bool route_over(const BirdState& b, const World& w);
// Where a flocking bird whose route is over steers on (flock.cpp: perceive): a whole last leg
// ahead of it along that leg, at the last target's height, so that its flock flies on as one
// (circling the last target, each bird steering for it from where it was, tore the flock apart
// there). None for a route of one target: its flock flies on by itself.
std::optional<glm::dvec3> onward_goal(const BirdState& b, const World& w);

// How far the bird still has to go along its route (cm): to its current target, then from target
// to target (where they are now) to the last, and on to its branch; 0 once perched. None for a
// route that loops without end.
std::optional<double> distance_to_go(const BirdState& b, const World& w);

// Whether the bird lands on the ground (Species::perches 0): its route's branch is a site on the
// ground. It does not brake: it glides down to it at its slowest airspeed, on a path kGlideSlope
// steep, lands where its legs meet the ground within perch_radius of the site and runs out on
// them (docs/MODEL.md "Landing on the ground").
bool lands_on_ground(const Species& s);

// Whether a bird that lands on the ground, its legs meeting the ground at `at`, has landed: on its
// route's site, within perch_radius of it (horizontally).
bool at_landing_site(const BirdState& b, const Species& s, const World& w, const glm::dvec3& at);

// For a bird whose route has brought it to its branch: starts braking (the flare) within
// brake_distance, or sooner where it must already brake at kBrakeShare of its full flare; goes
// round when it overshoots (flown past, out of perch_radius) or has sunk under the branch still
// sinking fast (kSunkPerchRadii, kSunkTouchdowns); perches within perch_radius at
// touchdown_speed or slower, or hovering onto the branch point (Species::hover_final) where its
// feet meet it (kGripReach), at touchdown_speed or slower over its last wingbeat
// (last_beat_speed). Returns true once perched.
bool approach_branch(BirdState& b, const Species& s, const World& w);

// Its mean speed over the ground over its last wingbeat period, or kTouchdownWindow when that is
// longer: this wingbeat's path so far, and the rest of the window at the last whole wingbeat's
// mean.
double last_beat_speed(const BirdState& b);

}  // namespace aeroflock
