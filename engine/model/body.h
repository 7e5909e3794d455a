// The body: rotation (eqs. 11-14 with the attitude as a quaternion) and ground effect (eq. 15).
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "bird.h"
#include "species.h"

namespace aeroflock {

// eq. 14 for a quaternion: q(t + dt) = normalize(q + dt/2 q (0, omega)), omega in the body frame.
glm::dquat integrate_attitude(const glm::dquat& q, const glm::dvec3& omega_body, double dt);

// eqs. 11, 12: angular acceleration of the box from a body-frame torque.
glm::dvec3 angular_acceleration(const Inertia& inertia, const glm::dvec3& torque);

// eq. 15: the upward ground-effect force k G m / max(h, floor) while 0 < h / l < 1, else 0. dyn.
double ground_effect_force(const Species& s, double height);
// The least height eq. 15 is evaluated at: half the body box's height (box_b / 2), where the
// body's underside meets the ground. cm.
double ground_effect_floor(const Species& s);

// Bank: the angle of the body's right axis below the horizon (right wing down > 0). Pitch: the
// angle of the head direction above the horizon.
double bank_angle(const glm::dquat& attitude);
double pitch_angle(const glm::dquat& attitude);

// The horizontal part of a world vector.
inline glm::dvec3 horizontal(const glm::dvec3& v) { return {v.x, 0.0, v.z}; }

// The attitude of a bird facing `heading` (from +x towards +z), level.
glm::dquat heading_attitude(double heading);

// Level, facing where `attitude`'s head points horizontally (+x when it points straight up or
// down): heading_attitude of that heading, computed without trigonometry (the compute shader does
// it inside its step loop).
glm::dquat level_attitude(const glm::dquat& attitude);
// Level, facing `head`'s horizontal direction (+x when it has none).
glm::dquat facing(const glm::dvec3& head);

// Brings a bird to rest at `at`: still, level, facing where it faced, wings and tail folded (the
// end of its settling after a grip or a touch-down, step.h: settle).
void come_to_rest(BirdState& b, const glm::dvec3& at);

// A bird holds on where it touches down (grips its branch: `perched`; stands on the ground:
// `standing`): its mode's clock restarts and it settles onto `at` from where it is (step.h:
// settle), its LandingStage `settling`, `at` kept in via_point.
void hold_on(BirdState& b, FlightMode mode, const glm::dvec3& at);

// The angle (rad) a body turns from attitude `a` to `b`, the shorter way round.
double turn_angle(const glm::dquat& a, const glm::dquat& b);

// `q` turned towards `to` by at most `angle` (rad), the shorter way round: `to` when it is nearer.
glm::dquat turn_towards(const glm::dquat& q, const glm::dquat& to, double angle);

}  // namespace aeroflock
