#include "gpu/layout.h"

#include <cmath>

#include "model/constants.h"

namespace aeroflock::gpu {

GpuBird pack(const BirdState& b) {
  GpuBird g;
  g.position_phase = glm::vec4(glm::vec3(b.position), float(b.phase));
  g.velocity_frequency = glm::vec4(glm::vec3(b.velocity), float(b.frequency));
  g.attitude = glm::vec4(float(b.attitude.x), float(b.attitude.y), float(b.attitude.z), float(b.attitude.w));
  g.omega_amplitude = glm::vec4(glm::vec3(b.omega), float(b.amplitude));
  g.tail_times = glm::vec4(float(b.tail_bend), float(b.tail_twist), float(b.mode_time), float(b.takeoff_time));
  g.via_progress = glm::vec4(glm::vec3(b.via_point), float(b.landing_progress));
  g.landing_start = glm::vec4(glm::vec3(b.landing_start), 0.0f);
  g.ids = glm::uvec4(uint32_t(b.mode) | uint32_t(b.landing_stage) << 8 | b.species << 16, b.route,
                     b.target, b.targets_reached);
  return g;
}

BirdState unpack(const GpuBird& g) {
  BirdState b;
  b.position = glm::dvec3(glm::vec3(g.position_phase));
  b.phase = g.position_phase.w;
  b.velocity = glm::dvec3(glm::vec3(g.velocity_frequency));
  b.frequency = g.velocity_frequency.w;
  b.attitude = glm::dquat(g.attitude.w, g.attitude.x, g.attitude.y, g.attitude.z);
  b.omega = glm::dvec3(glm::vec3(g.omega_amplitude));
  b.amplitude = g.omega_amplitude.w;
  b.tail_bend = g.tail_times.x;
  b.tail_twist = g.tail_times.y;
  b.mode_time = g.tail_times.z;
  b.takeoff_time = g.tail_times.w;
  b.via_point = glm::dvec3(glm::vec3(g.via_progress));
  b.landing_progress = g.via_progress.w;
  b.landing_start = glm::dvec3(glm::vec3(g.landing_start));
  b.mode = FlightMode(g.ids.x & 0xffu);
  b.landing_stage = LandingStage((g.ids.x >> 8) & 0xffu);
  b.species = g.ids.x >> 16;
  b.route = g.ids.y;
  b.target = g.ids.z;
  b.targets_reached = g.ids.w;
  return b;
}

GpuSpecies pack(const Species& s) {
  const Inertia inertia = box_inertia(s);
  const double arm_length = s.arm_fraction * s.wing_length;
  const double arm_area = s.arm_area_fraction * 0.5 * s.wing_area;
  auto f = [](double v) { return static_cast<float>(v); };
  return GpuSpecies{
      f(s.mass), f(1.0 / inertia.x), f(1.0 / inertia.y), f(1.0 / inertia.z),
      f(s.f_min), f(s.f_max), f(s.K_f), f(s.amp_min),
      f(s.amp_max), f(s.K_a), f(s.bend_max), f(s.rot_max),
      f(s.tail_min), f(s.Ct), f(s.ground_k), f(s.wing_length),
      f(s.A_arm), f(s.A_hand), f(s.lag_hand), f(s.B_arm),
      f(s.B_hand), f(s.C_leadlag), f(s.flap_bias), f(s.twist_bias),
      f(s.shoulder_x), f(0.5 * s.box_c - s.wing_length), f(arm_length), f(s.wing_length - arm_length),
      f(arm_area), f(0.5 * s.wing_area - arm_area), f(s.Cl_max), f(s.Cd_0),
      f(s.Cd_90), f(s.tail_incidence), f(-0.5 * s.box_a), f(2.0 / 3.0 * s.tail_length),
      // eq. 9: S_t = pi lr^2 phi / 360 (phi in degrees) = lr^2 / 2 * phi (phi in radians).
      f(0.5 * s.tail_length * s.tail_length), f(s.tail_rate), f(s.tail_roll_max), f(s.turn_rate),
      f(s.dead_band), f(s.heading_lead), f(s.height_lead), f(s.height_band),
      f(s.bank_max), f(std::tan(s.bank_max)), f(s.steer_full_error), f(s.roll_rate),
      f(s.bank_time), f(s.stand_height), f(s.crouch_time), f(s.crouch_depth),
      f(s.leg_force), f(s.leg_time), f(s.push_angle), f(s.approach_distance),
      f(s.brake_distance), f(s.brake_pitch), f(s.perch_radius),
      f(s.Ct * std::max(s.bend_max, s.rot_max) + s.tail_min),
      f(s.box_b), 0.0f, 0.0f, 0.0f};
}

std::vector<GpuTarget> pack_targets(const World& w, double time) {
  std::vector<GpuTarget> out;
  for (const Target& t : w.targets)
    out.push_back({glm::vec4(glm::vec3(target_position(t, time)), float(t.radius)),
                   glm::vec4(glm::vec3(t.velocity), 0.0f)});
  return out;
}

GpuWorld pack(const World& w) {
  GpuWorld g;
  g.targets = pack_targets(w, 0.0);
  for (const Route& r : w.routes) {
    g.routes.push_back({uint32_t(g.route_targets.size()), uint32_t(r.targets.size()),
                        (r.loop ? 1u : 0u) | (r.path_control ? 2u : 0u), uint32_t(r.branch + 1)});
    g.route_targets.insert(g.route_targets.end(), r.targets.begin(), r.targets.end());
  }
  for (const Branch& b : w.branches)
    g.branches.push_back({glm::vec4(glm::vec3(b.point), 0.0f), glm::vec4(glm::vec3(b.direction), 0.0f)});
  return g;
}

}  // namespace aeroflock::gpu
