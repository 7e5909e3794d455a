#include "gpu/layout.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include "model/tail.h"

namespace aeroflock::gpu {
namespace {

// std430 as host_device.h lays it out: the sizes the shaders see (tests/test_host_device.cpp
// compares every member with the shaders' SPIR-V).
static_assert(sizeof(GpuBird) % 16 == 0);
static_assert(sizeof(GpuSpecies) % 4 == 0);
static_assert(sizeof(GpuTarget) == 48 && sizeof(GpuRoute) == 16 && sizeof(GpuBranch) == 48);
static_assert(sizeof(GpuForces) == 12 * 16);
static_assert(sizeof(StepConstants) == 112 && sizeof(PoseConstants) == 48);
static_assert(sizeof(GpuWakeSource) == 64);
static_assert(sizeof(GpuPerception) == 48 + 64 * kGpuWakeSources &&
              kGpuWakeSources == kWakeSources);
static_assert(sizeof(Pose) == 19 * 16 && sizeof(FrameConstants) == 128);

// One field each way: doubles to floats, quaternions to (x, y, z, w), enums to uint.
float to_gpu(double v) { return static_cast<float>(v); }
vec3 to_gpu(const glm::dvec3& v) { return vec3(v); }
vec4 to_gpu(const glm::dquat& q) { return vec4(float(q.x), float(q.y), float(q.z), float(q.w)); }
uint to_gpu(uint32_t v) { return v; }
uvec2 to_gpu(uint64_t v) { return uvec2(uint32_t(v), uint32_t(v >> 32)); }
template <class E>
requires std::is_enum_v<E> uint to_gpu(E e) { return static_cast<uint>(e); }

void from_gpu(float v, double& out) { out = v; }
void from_gpu(const vec3& v, glm::dvec3& out) { out = glm::dvec3(v); }
void from_gpu(const vec4& v, glm::dquat& out) { out = glm::dquat(v.w, v.x, v.y, v.z); }
void from_gpu(uint v, uint32_t& out) { out = v; }
void from_gpu(const uvec2& v, uint64_t& out) { out = uint64_t(v.x) | uint64_t(v.y) << 32; }
template <class E>
requires std::is_enum_v<E>
void from_gpu(uint v, E& out) { out = static_cast<E>(v); }

}  // namespace

glm::dvec3 tile_centre(int tile_x, int tile_z) {
  return glm::dvec3(tile_x * kTile, 0.0, tile_z * kTile);
}

Tiled tiled(const glm::dvec3& world) {
  const glm::ivec2 tile(glm::round(glm::dvec2(world.x, world.z) / kTile));
  return {tile, tile_centre(tile.x, tile.y)};
}

GpuBird pack(const BirdState& b) {
  GpuBird g{};
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) g.name = to_gpu(b.name);
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
  // The points in the world, from the bird's tile.
  const Tiled t = tiled(b.position);
  g.tile_x = t.tile.x;
  g.tile_z = t.tile.y;
  g.position = to_gpu(b.position - t.centre);
  g.landing_start = to_gpu(b.landing_start - t.centre);
  g.via_point = to_gpu(b.via_point - t.centre);
  return g;
}

BirdState unpack(const GpuBird& g) {
  BirdState b;
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) from_gpu(g.name, b.name);
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
  const glm::dvec3 centre = tile_centre(g.tile_x, g.tile_z);
  b.position += centre;
  b.landing_start += centre;
  b.via_point += centre;
  return b;
}

GpuSpecies pack(const Species& s) {
  GpuSpecies g{};
#define AF_SPECIES_PARAM(name, default_value, unit, rule, max) g.name = to_gpu(s.name);
#include "model/species.def"
#undef AF_SPECIES_PARAM
  // What the step derives from the species (host_device.h lists them).
  const Inertia inertia = box_inertia(s);
  const double arm_length = s.arm_fraction * s.wing_length;
  const double arm_area = s.arm_area_fraction * 0.5 * s.wing_area;
  g.inv_inertia_x = to_gpu(1.0 / inertia.x);
  g.inv_inertia_y = to_gpu(1.0 / inertia.y);
  g.inv_inertia_z = to_gpu(1.0 / inertia.z);
  g.shoulder_z = to_gpu(0.5 * s.box_c - s.wing_length);
  g.arm_length = to_gpu(arm_length);
  g.hand_length = to_gpu(s.wing_length - arm_length);
  g.arm_area = to_gpu(arm_area);
  g.hand_area = to_gpu(0.5 * s.wing_area - arm_area);
  g.tail_hinge_x = to_gpu(-0.5 * s.box_a);
  g.tail_arm = to_gpu(2.0 / 3.0 * s.tail_length);
  // eq. 9: S_t = pi lr^2 phi / 360 (phi in degrees) = lr^2 / 2 * phi (phi in radians).
  g.tail_area_per_radian = to_gpu(0.5 * s.tail_length * s.tail_length);
  g.tan_bank_max = to_gpu(std::tan(s.bank_max));
  g.open_tail = to_gpu(open_tail(s));
  return g;
}

StepForces unpack(const GpuForces& g) {
  auto v = [](const vec4& x) { return glm::dvec3(vec3(x)); };
  StepForces f;
  for (int i = 0; i < 4; ++i) f.wing[i] = v(g.wing[i]);
  f.tail = v(g.tail);
  f.ground = v(g.ground);
  f.legs = v(g.legs);
  f.gravity = v(g.gravity);
  f.total = v(g.total);
  f.tail_torque = v(g.tail_torque);
  f.torque = v(g.torque);
  f.wake_air = v(g.wake_air_power);
  f.power = g.wake_air_power.w;
  return f;
}

WakeSource unpack(const GpuWakeSource& g) {
  WakeSource w;
  w.position = glm::dvec3(vec3(g.position_phase));
  w.phase = g.position_phase.w;
  w.air_velocity = glm::dvec3(vec3(g.air_velocity_frequency));
  w.frequency = g.air_velocity_frequency.w;
  from_gpu(g.attitude, w.attitude);
  w.lift = g.lift_amplitude.x;
  w.amplitude = g.lift_amplitude.y;
  return w;
}

GpuWakeSource pack(const WakeSource& w) {
  return {vec4(vec3(w.position), float(w.phase)), vec4(vec3(w.air_velocity), float(w.frequency)),
          to_gpu(w.attitude), vec4(float(w.lift), float(w.amplitude), 0.0f, 0.0f)};
}

GpuPerception pack(const Perception& p) {
  GpuPerception g{vec3(p.direction),
                  float(p.airspeed),
                  p.neighbours,
                  float(p.nearest),
                  p.seen_key,
                  p.wakes,
                  p.wake_step,
                  0,
                  0,
                  float(p.phase_rate),
                  {}};
  for (uint32_t k = 0; k < kWakeSources; ++k) g.wake[k] = pack(p.wake[k]);
  return g;
}

Perception unpack(const GpuPerception& g) {
  Perception p{glm::dvec3(g.direction),
               double(g.airspeed),
               g.neighbours,
               double(g.nearest),
               g.seen_key,
               g.wakes,
               g.wake_step,
               {}};
  for (uint32_t k = 0; k < kWakeSources; ++k) p.wake[k] = unpack(g.wake[k]);
  p.phase_rate = g.phase_rate;
  return p;
}

GpuTarget pack_target(const Target& t, const glm::dvec3& centre) {
  const Tiled at = tiled(centre);
  return {vec4(vec3(centre - at.centre), float(t.radius)), vec4(vec3(t.velocity), 0.0f), at.tile.x,
          at.tile.y};
}

std::vector<GpuTarget> pack_targets(const World& w, double time) {
  std::vector<GpuTarget> out;
  for (const Target& t : w.targets) out.push_back(pack_target(t, target_position(t, time)));
  return out;
}

std::vector<uint32_t> model_constants(const Scenario& scenario, std::span<const BirdState> birds) {
  const World& w = scenario.world;
  const bool branches =
      std::any_of(w.routes.begin(), w.routes.end(), [](const Route& r) { return r.branch >= 0; }) ||
      std::any_of(birds.begin(), birds.end(),
                  [](const BirdState& b) { return b.mode == FlightMode::landing; });
  std::vector<uint32_t> c(kModelConstants);
  c[kConstantWakes] = any_wake(scenario) ? 1u : 0u;
  c[kConstantBranches] = branches ? 1u : 0u;
  c[kConstantWindProfile] = static_cast<uint32_t>(w.wind_profile);
  return c;
}

GpuWorld pack(const World& w) {
  GpuWorld g;
  for (const Route& r : w.routes) {
    g.routes.push_back({uint32_t(g.route_targets.size()), uint32_t(r.targets.size()),
                        (r.loop ? kRouteLoop : 0u) | (r.path_control ? kRoutePathControl : 0u),
                        uint32_t(r.branch + 1)});
    g.route_targets.insert(g.route_targets.end(), r.targets.begin(), r.targets.end());
  }
  for (const Branch& b : w.branches) {
    const Tiled at = tiled(b.point);
    g.branches.push_back({vec4(vec3(b.point - at.centre), 0.0f), vec4(vec3(b.direction), 0.0f),
                          at.tile.x, at.tile.y});
  }
  return g;
}

}  // namespace aeroflock::gpu
