// engine/model/body.cpp in float (model.glsl), function for function in its order; the reasons
// are in the C++. heading_attitude is the host's (setting birds up).

// glm::conjugate(q) * v: from the world to the body frame.
vec3 rotate_back(vec4 q, vec3 v) { return rotate(vec4(-q.xyz, q.w), v); }
vec3 horizontal(vec3 v) { return vec3(v.x, 0.0, v.z); }  // body.h

// eq. 14 for a quaternion: q + dt/2 q (omega, 0), renormalised.
vec4 integrate_attitude(vec4 q, vec3 omega, float dt) {
  precise vec4 dq = vec4(q.w * omega + cross(q.xyz, omega), -dot(q.xyz, omega));
  precise vec4 r = q + (0.5 * dt) * dq;
  return normalize(r);
}

// species.h: Inertia and species.cpp: box_inertia (eq. 12), held inverted (layout.cpp).
struct Inertia {
  vec3 inverse;
};
Inertia box_inertia(GpuSpecies s) {
  return Inertia(vec3(s.inv_inertia_x, s.inv_inertia_y, s.inv_inertia_z));
}

vec3 angular_acceleration(Inertia inertia, vec3 torque) {
  precise vec3 a = torque * inertia.inverse;
  return a;
}

float ground_effect_floor(GpuSpecies s) { return 0.5 * s.box_b; }

float ground_effect_force(GpuSpecies s, float height) {  // eq. 15
  return height > 0.0 && height < s.wing_length
             ? s.ground_k * kGravity * s.mass / max(height, ground_effect_floor(s))
             : 0.0;
}

float bank_angle(vec4 q) { return asin_p(clamp(-rotate(q, vec3(0, 0, 1)).y, -1.0, 1.0)); }
float pitch_angle(vec4 q) { return asin_p(clamp(rotate(q, vec3(1, 0, 0)).y, -1.0, 1.0)); }

vec4 facing(vec3 head);  // declared ahead (body.h)
vec4 level_attitude(vec4 q) { return facing(rotate(q, vec3(1, 0, 0))); }

vec4 facing(vec3 head) {
  float n = length(head.xz);
  if (!(n > 0.0)) return vec4(0.0, 0.0, 0.0, 1.0);  // head straight up or down: facing +x
  float hx = head.x / n, hz = head.z / n;
  float w = hx >= 0.0 ? 1.0 + hx : abs(hz);
  float y = hx >= 0.0 ? -hz : (hz < 0.0 ? 1.0 - hx : hx - 1.0);
  return vec4(0.0, y, 0.0, w) / length(vec2(w, y));
}

void come_to_rest(inout GpuBird b, vec3 at) {
  b.position = at;
  b.velocity = vec3(0.0);
  b.omega = vec3(0.0);
  b.attitude = level_attitude(b.attitude);
  b.amplitude = 0.0;
  b.tail_bend = 0.0;
  b.tail_twist = 0.0;
}

void hold_on(inout GpuBird b, uint mode, vec3 at) {
  b.mode = mode;
  b.mode_steps = 0u;
  b.landing_stage = stage_settling;
  b.via_point = at;
}

// Quaternions (x, y, z, w): a b, as glm's operator*.
vec4 quat_mul(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

float turn_angle(vec4 a, vec4 b) {
  float w = min(1.0, abs(dot(a, b)));
  return 2.0 * atan_p(sqrt(1.0 - w * w), w);
}

vec4 turn_towards(vec4 q, vec4 to, float angle) {
  vec4 r = quat_mul(to, vec4(-q.xyz, q.w));
  if (r.w < 0.0) r = -r;
  float s = length(r.xyz);
  if (s == 0.0 || 2.0 * atan_p(s, r.w) <= angle) return to;
  float c = cos_p(0.5 * angle), k = sin_p(0.5 * angle) / s;
  return normalize(quat_mul(vec4(k * r.xyz, c), q));
}
