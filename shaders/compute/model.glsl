// The bird model of engine/model, function for function, in float. Force and integration
// statements are `precise` so that they are not contracted into FMAs: the CPU reference is built
// with -ffp-contract=off, and the two then differ only by float-vs-double rounding. The includer
// declares the buffers (buffers.glsl) and the push constants `pc` (StepConstants).

#include "bird.glsl"

vec3 rotate_back(vec4 q, vec3 v) { return rotate(vec4(-q.xyz, q.w), v); }

// eq. 14 for a quaternion: q + dt/2 q (omega, 0), renormalised.
vec4 integrate_attitude(vec4 q, vec3 omega, float dt) {
  precise vec4 dq = vec4(q.w * omega + cross(q.xyz, omega), -dot(q.xyz, omega));
  precise vec4 r = q + (0.5 * dt) * dq;
  return normalize(r);
}

float bank_angle(vec4 q) { return asin_p(clamp(-rotate(q, vec3(0, 0, 1)).y, -1.0, 1.0)); }
float pitch_angle(vec4 q) { return asin_p(clamp(rotate(q, vec3(1, 0, 0)).y, -1.0, 1.0)); }
vec3 horizontal(vec3 v) { return vec3(v.x, 0.0, v.z); }

// Level, facing the horizontal direction h of `head` (body.cpp: facing, level_attitude): the turn
// about the vertical from +x to h, as the half-way quaternion.
vec4 facing(vec3 head) {
  float n = length(head.xz);
  if (!(n > 0.0)) return vec4(0.0, 0.0, 0.0, 1.0);  // head straight up or down: facing +x
  float hx = head.x / n, hz = head.z / n;
  float w = hx >= 0.0 ? 1.0 + hx : abs(hz);
  float y = hx >= 0.0 ? -hz : (hz < 0.0 ? 1.0 - hx : hx - 1.0);
  return vec4(0.0, y, 0.0, w) / length(vec2(w, y));
}
vec4 level_attitude(vec4 q) { return facing(rotate(q, vec3(1, 0, 0))); }

// eq. 15, h no less than the body box's half height (body.cpp: ground_effect_floor)
float ground_effect_force(GpuSpecies s, float height) {
  return height > 0.0 && height < s.wing_length
             ? s.ground_k * kGravity * s.mass / max(height, 0.5 * s.box_b)
             : 0.0;
}

// --- Aerodynamics (eqs. 1, 2; aerodynamics.cpp) ---------------------------------------------

vec3 aerodynamic_force(GpuSpecies s, vec3 air, vec3 chord, vec3 normal, float area) {
  precise float u_chord = dot(air, chord);
  precise float u_normal = dot(air, normal);
  precise float speed2 = u_chord * u_chord + u_normal * u_normal;
  if (!(speed2 > 0.0)) return vec3(0.0);
  precise float speed = sqrt(speed2);
  precise float sin_a = u_normal / speed;
  precise float cos_a = -u_chord / speed;
  precise float cl = s.Cl_max * 2.0 * sin_a * cos_a;
  precise float cd = s.Cd_0 + (s.Cd_90 - s.Cd_0) * sin_a * sin_a;
  precise float q_area = 0.5 * kAirDensity * speed2 * area;
  precise vec3 lift_dir = chord * sin_a + normal * cos_a;
  precise vec3 drag_dir = chord * -cos_a + normal * sin_a;
  precise vec3 f = q_area * (cl * lift_dir + cd * drag_dir);
  return f;
}

// --- Wingbeat (wingbeat.cpp) ------------------------------------------------------------------

struct WingPoint {
  vec3 position, velocity, chord, normal;
  float area;
};

void flap(inout vec3 fy, inout vec3 fz, float angle) {
  vec2 sc = sin_cos(angle);
  float c = sc.y, s = sc.x;
  vec3 y = c * fy - s * fz;
  vec3 z = s * fy + c * fz;
  fy = y;
  fz = z;
}

void feather(vec3 fx, vec3 fy, float angle, out vec3 chord, out vec3 normal) {
  vec2 sc = sin_cos(angle);
  float c = sc.y, s = sc.x;
  chord = c * fx - s * fy;
  normal = s * fx + c * fy;
}

void right_wing_points(GpuSpecies s, float phase, float amp, float frequency, float sweep,
                       float incidence, out WingPoint arm, out WingPoint hand) {
  WingAngles w = wing_angles(s, phase, amp, sweep, incidence);
  float phase_rate = 2.0 * kPi * frequency;
  float leadlag_rate = s.C_leadlag * w.cos_phase * phase_rate;
  float flap_arm_rate = -amp * s.A_arm * w.sin_phase * phase_rate;
  float flap_hand_rate = -amp * s.A_hand * w.sin_hand_phase * phase_rate;

  vec2 l = sin_cos(w.leadlag);
  float cl = l.y, sl = l.x;
  vec3 sx = vec3(cl, 0.0, -sl), sy = vec3(0.0, 1.0, 0.0), sz = vec3(sl, 0.0, cl);
  vec3 ax = sx, ay = sy, az = sz;
  flap(ay, az, w.flap_arm);
  vec3 hx = ax, hy = ay, hz = az;
  flap(hy, hz, w.flap_hand);

  vec3 shoulder = vec3(s.shoulder_x, 0.0, s.shoulder_z);
  vec3 wrist = shoulder + az * s.arm_length;
  arm.position = shoulder + az * (0.5 * s.arm_length);
  hand.position = wrist + hz * (0.5 * s.hand_length);
  vec3 omega_shoulder = vec3(0.0, leadlag_rate, 0.0) - sx * flap_arm_rate;
  vec3 omega_wrist = -ax * flap_hand_rate;
  arm.velocity = cross(omega_shoulder, arm.position - shoulder);
  hand.velocity =
      cross(omega_shoulder, hand.position - shoulder) + cross(omega_wrist, hand.position - wrist);
  feather(ax, ay, w.feather_arm, arm.chord, arm.normal);
  feather(hx, hy, w.feather_arm + w.feather_hand, hand.chord, hand.normal);
  arm.area = s.arm_area;
  hand.area = s.hand_area;
}

WingPoint mirror_to_left(WingPoint p) {
  vec3 m = vec3(1.0, 1.0, -1.0);
  p.position *= m;
  p.velocity *= m;
  p.chord *= m;
  p.normal *= m;
  return p;
}

// --- Tail (eqs. 9, 10; tail.cpp) ------------------------------------------------------------

void tail_geometry(GpuSpecies s, float bend, float twist, out vec3 position, out vec3 chord,
                   out vec3 normal) {
  float pitch = s.tail_incidence + bend;
  vec2 p = sin_cos(pitch), t = sin_cos(twist);
  float cp = p.y, sp = p.x, ct = t.y, st = t.x;
  vec3 trailing = vec3(-cp, ct * sp, st * sp);
  position = vec3(s.tail_hinge_x, 0.0, 0.0) + trailing * s.tail_arm;
  chord = vec3(cp, -ct * sp, -st * sp);
  normal = vec3(sp, ct * cp, st * cp);
}

// --- Control (control.cpp) ------------------------------------------------------------------

float sign_outside(float x, float band) { return x > band ? 1.0 : (x < -band ? -1.0 : 0.0); }

float steer_share(GpuSpecies s, float heading_error) {
  if (abs(heading_error) <= s.dead_band) return 0.0;
  return clamp(heading_error / s.steer_full_error, -1.0, 1.0);
}

struct Steering {
  float heading_error, heading_error_ahead, height_error;
  float aim_speed;  // |crab_aim| (control.h)
  float air_speed;  // horizontal, through the air
};

vec2 crab_aim(vec3 to_goal, vec3 wind, float ground_speed) {
  float len = length(to_goal.xz);
  return len == 0.0 ? vec2(0.0) : to_goal.xz * (ground_speed / len) - wind.xz;
}

float approach_speed(GpuSpecies s, float to_branch) {
  if (to_branch < 0.0) return s.cruise_speed;
  float room = max(0.0, to_branch - s.perch_radius);
  return min(s.cruise_speed,
             sqrt(s.touchdown_speed * s.touchdown_speed + 2.0 * s.brake_decel * room));
}

Steering steer_towards(GpuSpecies s, vec4 attitude, float bank, vec3 position, vec3 velocity,
                       vec3 goal, vec3 wind, float ground_speed, bool by_course) {
  // Braking: the course through the air, or the head's direction when the bird barely moves through
  // it.
  vec3 air = velocity - wind;
  Steering st;
  st.air_speed = length(air.xz);
  vec3 head = by_course && st.air_speed > kSteerAirspeed ? air : rotate(attitude, vec3(1, 0, 0));
  vec3 to_goal = goal - position;
  vec2 aim = crab_aim(to_goal, wind, ground_speed);
  st.heading_error = atan_p(-head.z * aim.x + head.x * aim.y, head.x * aim.x + head.z * aim.y);
  float turn_rate = st.air_speed > 1.0 ? kGravity * tan_p(bank) / st.air_speed
                                       : 0.0;  // as the bank (control.cpp)
  st.heading_error_ahead = st.heading_error - s.heading_lead * turn_rate;
  st.height_error = to_goal.y - s.height_lead * velocity.y;
  st.aim_speed = length(aim);
  return st;
}

void turn_on(GpuSpecies s, float bank, inout Steering st) {  // control.cpp
  if (abs(bank) <= 0.5 * s.bank_max || abs(st.heading_error) <= kBehind) return;
  float turn = bank > 0.0 ? 1.0 : -1.0;
  if (st.heading_error * turn > 0.0) return;
  st.heading_error += turn * 2.0 * kPi;
  st.heading_error_ahead += turn * 2.0 * kPi;
}

float rate_step(float value, float lo, float hi, float rate, float dy, float dt) {
  return clamp(value + sign(dy) * rate * dt, lo, hi);
}

float approach(float angle, float command, float rate, float dt) {
  float step = rate * dt;
  return angle + clamp(command - angle, -step, step);
}

float coordinated_bank(GpuSpecies s, float turn_rate, float speed) {
  return clamp(atan_p(speed * turn_rate / kGravity), -s.bank_max, s.bank_max);
}

float full_bank_radius(GpuSpecies s, float speed) {
  return kWideTurn * speed * speed / (kGravity * s.tan_bank_max);
}

bool circles_goal(float heading_error, float distance, float radius, float speed, float rise,
                  float wind) {
  if (2.0 * kPi * wind >= speed) return false;  // control.cpp
  return abs(rise) < kLevelGoal * distance && distance < 2.0 * radius * abs(sin_p(heading_error));
}

float heading_bank(GpuSpecies s, float heading_error, float distance, float speed) {
  if (abs(heading_error) <= s.dead_band) return 0.0;
  if (abs(heading_error) >= 0.5 * kPi) return heading_error > 0.0 ? s.bank_max : -s.bank_max;
  float rate = heading_error / s.turn_time;
  float tightest = speed * speed / (kGravity * s.tan_bank_max);
  float pursuit = 2.0 * speed * sin_p(heading_error) / max(distance, tightest);
  if (abs(pursuit) > abs(rate)) rate = pursuit;
  return coordinated_bank(s, rate, speed);
}

float recovery_bank(GpuSpecies s, float pitch, float descent, float airspeed) {
  float by_pitch = (kSteepPitch - abs(pitch)) / (kSteepPitch / 2.0);
  float by_descent = (kSteepDescent - descent) / (kSteepDescent / 2.0);
  float by_speed = (kDiveSpeed * s.max_speed - airspeed) / (0.5 * s.max_speed);
  return s.bank_max * clamp(min(by_pitch, min(by_descent, by_speed)), 0.0, 1.0);
}

float descent_angle(float air_climb, float airspeed) {
  return airspeed > 0.0 ? max(0.0, -asin_p(clamp(air_climb / airspeed, -1.0, 1.0))) : 0.0;
}

float ground_bank(GpuSpecies s, float height) {
  return asin_p(clamp(height / s.wing_length, 0.0, 1.0));
}

// --- Airspeed, pitch and sweep (control.cpp) ---

float commanded_airspeed(GpuSpecies s, float command, float aim_speed, bool to_branch) {
  if (to_branch) return clamp(aim_speed, s.min_speed, s.max_speed);
  if (command > 0.0) return clamp(command, s.min_speed, s.max_speed);
  return clamp(aim_speed, s.cruise_speed, s.max_speed);
}

// x: the total energy error, y: the balance, cm.
vec2 energy_errors(GpuSpecies s, float height_error, float airspeed, float commanded) {
  precise float deficit = (commanded * commanded - airspeed * airspeed) / (2.0 * kGravity);
  float height_share =
      clamp((airspeed / s.min_speed - kSpeedFirst) / (1.0 - kSpeedFirst), 0.0, 1.0);
  return vec2(height_error + deficit,
              height_share * clamp(height_error, -s.balance_band, s.balance_band) - deficit);
}

float spool_lead(GpuSpecies s, float amplitude, float air_climb) {
  if (s.K_a <= 0.0 || air_climb >= 0.0) return 0.0;
  return 0.5 * (s.amp_max - amplitude) / s.K_a * -air_climb;
}

float commanded_pitch(GpuSpecies s, float pitch_trim, float balance, float height,
                      float goal_height) {
  float pitch = clamp(pitch_trim + s.balance_gain * balance, s.pitch_min, s.pitch_max);
  float floor_height = min(s.clearance, goal_height);
  if (height >= floor_height) return pitch;
  return max(pitch, s.climb_pitch * (1.0 - height / floor_height));
}

bool heeds_wind(GpuSpecies s, float speed) {
  return speed > kTouchdownAim * s.touchdown_speed;
}  // control.cpp

float perch_airspeed(GpuSpecies s, vec3 to_perch, vec3 wind) {
  return length(crab_aim(to_perch, wind, kTouchdownAim * s.touchdown_speed));
}

float flare_share(GpuSpecies s, float airspeed, float to_airspeed, float to_perch) {
  float room = max(to_perch - 0.5 * s.perch_radius, 0.1 * s.perch_radius);
  float needed = max(0.0, airspeed * airspeed - to_airspeed * to_airspeed) / (2.0 * room);
  return min(needed / s.flare_decel, 1.0);
}

float flare_pitch(GpuSpecies s, float pitch_trim, float share) {
  return clamp(pitch_trim + (s.brake_pitch - pitch_trim) * share, s.pitch_min, s.brake_pitch);
}

// x: the tail bend, y: the sweep.
vec2 pitch_control(GpuSpecies s, float pitch_command, float pitch, float rate) {
  float error = pitch_command - pitch - s.pitch_damping * rate;
  float beyond = error - clamp(error, -s.pitch_band, s.pitch_band);
  return vec2(clamp(s.pitch_gain * beyond, -s.bend_max, s.bend_max),
              clamp(s.sweep_gain * error, -s.sweep_max, s.sweep_max));
}

float pitch_rate(vec4 attitude, vec3 omega) {
  vec3 head = rotate(attitude, vec3(1, 0, 0));
  return cross(rotate(attitude, omega), head).y / sqrt(max(1.0 - head.y * head.y, 1e-6));
}

float bank_rate(vec4 attitude, vec3 omega) {
  vec3 right = rotate(attitude, vec3(0, 0, 1));
  return -cross(rotate(attitude, omega), right).y / sqrt(max(1.0 - right.y * right.y, 1e-6));
}

float roll_for_bank(GpuSpecies s, vec4 attitude, vec3 omega, float bank, float bank_command) {
  float wanted = (bank_command - bank) / s.bank_time;
  float per_roll = bank_rate(attitude, vec3(1, 0, 0));
  float roll = abs(per_roll) > 0.1
                   ? (wanted - bank_rate(attitude, vec3(0.0, omega.y, omega.z))) / per_roll
                   : wanted;
  return clamp(roll, -s.roll_rate, s.roll_rate);
}

vec3 landing_point(vec3 bird, vec3 heading, vec3 branch_point, vec3 branch_direction) {
  float hn = length(heading.xz);
  if (hn == 0.0) return branch_point;
  float hx = heading.x / hn, hz = heading.z / hn;
  float nx = -branch_direction.z, nz = branch_direction.x;
  float det = hx * (-nz) - hz * (-nx);
  if (abs(det) < kLinedUpSine) return branch_point;
  float dx = branch_point.x - bird.x, dz = branch_point.z - bird.z;
  float s = (dx * (-nz) - dz * (-nx)) / det;
  if (s <= 0.0 || s > kFarthestCrossing * length(vec2(dx, dz))) return branch_point;
  vec3 q3 = vec3(bird.x + s * hx, branch_point.y, bird.z + s * hz);
  return 0.25 * bird + 0.5 * q3 + 0.25 * branch_point;
}

vec3 landing_curve(vec3 q1, vec3 p, vec3 q2, float u) {
  vec3 q3 = 2.0 * p - 0.5 * (q1 + q2);
  float v = 1.0 - u;
  return v * v * q1 + 2.0 * u * v * q3 + u * u * q2;
}

float landing_progress(vec3 q1, vec3 p, vec3 q2, float u, vec3 position, float lookahead) {
  const float kStep = 1.0 / 128.0;
  vec3 q3 = 2.0 * p - 0.5 * (q1 + q2);
  while (u < 1.0) {
    vec3 at = landing_curve(q1, p, q2, u);
    vec3 tangent = (1.0 - u) * (q3 - q1) + u * (q2 - q3);
    bool behind = dot(at - position, tangent) < 0.0;
    if (!behind && distance(at, position) >= lookahead) break;
    u = min(1.0, u + kStep);
  }
  return u;
}

// --- The wind (world.cpp) ---------------------------------------------------------------------

// At world height y: pc.wind_ground.xyz at pc.wind_height above the ground, by the profile.
vec3 wind_at(float y) {
  if (pc.wind_profile == 0u) return pc.wind_ground.xyz;
  float h = y - pc.wind_ground.w;
  if (pc.wind_profile == 1u)
    return h > 0.0 ? pc.wind_ground.xyz * pow(h / pc.wind_height, pc.wind_exponent) : vec3(0.0);
  return h > pc.wind_roughness ? pc.wind_ground.xyz * (log(h / pc.wind_roughness) /
                                                       log(pc.wind_height / pc.wind_roughness))
                               : vec3(0.0);
}

// The wind where the bird is this step (step_bird sets it once: the step moves the bird only at
// its end); a private global rather than a parameter, which made glslang's precise propagation
// blow up (docs/ARCHITECTURE.md).
vec3 step_wind;

// --- Route and landing (route.cpp) ------------------------------------------------------------

vec3 perch_point(GpuBird b, GpuSpecies s, uint branch) {
  GpuBranch br = branches[branch];
  return br.point.xyz + tile_shift(br.tile_x, br.tile_z, b.tile_x, b.tile_z) +
         vec3(0.0, s.stand_height, 0.0);
}

// Moving away from the branch horizontally, out of perch_radius (route.cpp).
bool flown_past(GpuBird b, GpuSpecies s, vec3 to_perch) {
  return dot(to_perch.xz, b.velocity.xz) <= 0.0 && length(to_perch.xz) > s.perch_radius;
}

// Sunk under the perch and still sinking fast (route.cpp).
bool sunk_under(GpuBird b, GpuSpecies s, vec3 to_perch) {
  return to_perch.y > kSunkPerchRadii * s.perch_radius &&
         b.velocity.y < -kSunkTouchdowns * s.touchdown_speed;
}

bool into_wind(GpuSpecies s, vec3 across, vec3 wind) {
  return heeds_wind(s, abs(dot(wind, across)));
}

vec3 landing_gate(GpuSpecies s, vec3 across, vec3 q2, float side) {
  return q2 + across * (side * kGateApproaches * s.approach_distance);
}

void place_curve(inout GpuBird b, uint branch, vec3 q2) {
  b.landing_start = b.position;
  b.via_point = landing_point(b.position, rotate(b.attitude, vec3(1, 0, 0)), q2,
                              branches[branch].direction.xyz);
  b.landing_progress = 0.0;
}

vec3 landing_goal(inout GpuBird b, GpuSpecies s, uint branch, vec3 wind) {
  vec3 q2 = perch_point(b, s, branch);
  vec3 direction = branches[branch].direction.xyz;
  vec3 across = vec3(-direction.z, 0.0, direction.x);
  bool windward = into_wind(s, across, wind);
  float side = dot(windward ? wind : b.position - q2, across) < 0.0 ? -1.0 : 1.0;  // route.cpp
  vec3 track = horizontal(b.velocity), inward = horizontal(q2 - b.position);
  if (b.landing_stage == stage_none) {
    place_curve(b, branch, q2);
    bool heading_in = dot(track, inward) > 0.0;
    float out_side = windward ? s.approach_distance : 0.0;
    bool on_side = dot(b.position - q2, across) * side >= out_side;
    b.landing_stage =
        on_side && (any(notEqual(b.via_point, q2)) || heading_in) ? stage_curve : stage_gate;
  }
  if (b.landing_stage == stage_gate) {
    vec3 gate = landing_gate(s, across, q2, side);
    vec3 to_gate = horizontal(gate - b.position);
    float d = length(to_gate);
    bool gone_by = dot(to_gate, b.velocity) < 0.0;
    bool heading_out = dot(track, inward) < -kGateHeadingOut * length(track) * length(inward);
    if (heading_out ||
        (d > s.approach_distance && !(gone_by && d <= kMissedTargetRadii * s.approach_distance)))
      return gate;
    place_curve(b, branch, q2);
    b.landing_stage = stage_curve;
  }
  if (b.landing_progress >= 1.0 || all(equal(b.via_point, q2))) {
    if (flown_past(b, s, q2 - b.position)) b.landing_stage = stage_gate;
    return q2;
  }
  b.landing_progress = landing_progress(b.landing_start, b.via_point, q2, b.landing_progress,
                                        b.position, s.approach_distance);
  vec3 on_curve = landing_curve(b.landing_start, b.via_point, q2, b.landing_progress);
  return vec3(on_curve.x, q2.y, on_curve.z);  // at the perch's height (route.cpp)
}

// What a bird's route asks of it now: the route and its current (or, past the end, last)
// target, loaded from the buffers when the target changes (targets only move between frames).
struct Leg {
  GpuRoute route;
  vec4 centre_radius;
  vec3 velocity;
  uint targets_from;  // pc.targets_base: the targets at the frame's start; + pc.next_targets: at
                      // the next one's
};

Leg load_leg(GpuBird b, uint targets_from) {
  Leg l;
  l.targets_from = targets_from;
  l.route = routes[b.route];
  l.centre_radius = vec4(0.0);
  l.velocity = vec3(0.0);
  if (l.route.count > 0u) {
    GpuTarget t =
        targets[targets_from + route_targets[l.route.first + min(b.target, l.route.count - 1u)]];
    l.centre_radius =
        t.centre_radius + vec4(tile_shift(t.tile_x, t.tile_z, b.tile_x, b.tile_z), 0.0);
    l.velocity = t.velocity.xyz;
  }
  return l;
}

vec3 route_goal(inout GpuBird b, GpuSpecies s, inout Leg leg) {
  GpuRoute r = leg.route;
  if (b.target < r.count) {
    vec3 to_target = leg.centre_radius.xyz - b.position;
    float d = length(to_target);
    bool gone_by = dot(to_target, b.velocity - leg.velocity) < 0.0;
    if (d <= leg.centre_radius.w || (d <= kMissedTargetRadii * leg.centre_radius.w && gone_by)) {
      b.targets_reached += 1u;
      b.target += 1u;
      if (b.target == r.count && (r.flags & kRouteLoop) != 0u && r.branch == 0u) b.target = 0u;
      leg = load_leg(b, leg.targets_from);
    }
  }
  if (b.target < r.count || r.branch == 0u) return leg.centre_radius.xyz;
  uint branch = r.branch - 1u;
  return (r.flags & kRoutePathControl) != 0u ? landing_goal(b, s, branch, step_wind)
                                             : perch_point(b, s, branch);
}

void come_to_rest(inout GpuBird b, vec3 at) {
  b.position = at;
  b.velocity = vec3(0.0);
  b.omega = vec3(0.0);
  b.attitude = level_attitude(b.attitude);
  b.amplitude = 0.0;
  b.tail_bend = 0.0;
  b.tail_twist = 0.0;
  b.mode_time = 0.0;
}

void perch(inout GpuBird b, GpuSpecies s, uint branch) {
  come_to_rest(b, perch_point(b, s, branch));
  b.mode = mode_perched;
  b.targets_reached += 1u;
}

bool approach_branch(inout GpuBird b, GpuSpecies s, Leg leg) {
  GpuRoute r = leg.route;
  if (r.branch == 0u || b.target < r.count) return false;
  uint branch = r.branch - 1u;
  vec3 to_perch = perch_point(b, s, branch) - b.position;
  float d = length(to_perch);
  if (d <= s.perch_radius && length(b.velocity) <= s.touchdown_speed) {
    perch(b, s, branch);
    return true;
  }
  bool closing = dot(to_perch.xz, b.velocity.xz) > 0.0;  // heading in horizontally (route.cpp)
  if (b.mode == mode_landing && (flown_past(b, s, to_perch) || sunk_under(b, s, to_perch))) {
    b.mode = mode_flying;
    b.mode_time = 0.0;
    b.landing_stage = stage_none;
  } else if (b.mode == mode_flying && closing && b.landing_stage != stage_gate &&
             (d <= s.brake_distance ||
              flare_share(s, length(b.velocity - step_wind), perch_airspeed(s, to_perch, step_wind),
                          d) >= kBrakeShare)) {
    b.mode = mode_landing;
    b.mode_time = 0.0;
  }
  return false;
}

// --- One step (step.cpp) ----------------------------------------------------------------------

struct Commands {
  Steering steering;
  float energy_error;  // what eqs. 4, 5 follow, cm
  float balance;       // what the pitch trim integrates, cm
  float bend, twist;   // where the tail moves to
  float sweep;         // where the wings' sweep moves to
  float incidence;     // the arms' added incidence (braking)
  float opening;
  vec3 omega;
  bool circling;  // the goal lies inside the full-bank circle (step.cpp)
};

// xyz: the way to where the bird perches, w: its length, once the perch is its goal; w -1 before
// (on its way to the landing gate too), or without a branch (route.cpp: way_to_perch).
vec4 way_to_perch(GpuBird b, GpuSpecies s, Leg leg) {
  if (leg.route.branch == 0u || b.target < leg.route.count || b.landing_stage == stage_gate)
    return vec4(0.0, 0.0, 0.0, -1.0);
  vec3 way = perch_point(b, s, leg.route.branch - 1u) - b.position;
  return vec4(way, length(way));
}

Commands control(GpuBird b, GpuSpecies s, vec3 goal, vec4 way, float airspeed_command) {
  float to_perch = way.w;
  float ground = pc.wind_ground.w + s.stand_height;
  goal.y = max(goal.y, ground);  // no bird flies lower than it stands (step.cpp)
  bool on_legs = b.mode == mode_taking_off;
  bool braking = b.mode == mode_landing;
  if (braking) goal.y += kFlareAimAbove * s.perch_radius;
  bool fixed_rate = pc.turning == 1u && !braking;
  Commands c;
  float bank = bank_angle(b.attitude);
  float pitch = pitch_angle(b.attitude);
  vec3 wind = step_wind;
  c.steering = steer_towards(s, b.attitude, bank, b.position, b.velocity, goal, wind,
                             approach_speed(s, to_perch), braking);
  bool to_target = to_perch < 0.0 && b.landing_stage == stage_none;  // step.cpp
  if (to_target && !fixed_rate) turn_on(s, bank, c.steering);
  c.twist = steer_share(s, fixed_rate ? c.steering.heading_error : c.steering.heading_error_ahead) *
            s.rot_max;
  c.twist = clamp(c.twist, min(0.0, -s.tail_roll_max - bank), max(0.0, s.tail_roll_max - bank));
  c.opening = tail_opening(s, b);

  float airspeed = length(b.velocity - wind);
  float air_climb = b.velocity.y - wind.y;
  float commanded = commanded_airspeed(s, airspeed_command, c.steering.aim_speed, to_perch >= 0.0);
  vec2 e = energy_errors(s, c.steering.height_error, airspeed, commanded);
  c.energy_error = braking ? c.steering.height_error : e.x + spool_lead(s, b.amplitude, air_climb);
  if (pitch > (braking ? s.brake_pitch : s.pitch_max) + kPitchOverrun)
    c.energy_error = min(c.energy_error, 0.0);                                         // step.cpp
  if (pitch < s.pitch_min - kPitchOverrun) c.energy_error = max(c.energy_error, 1.0);  // step.cpp
  c.balance = e.y;
  float flare = braking && to_perch >= 0.0
                    ? flare_share(s, airspeed, perch_airspeed(s, way.xyz, wind), to_perch)
                    : 0.0;
  c.incidence = s.brake_incidence * flare * min(b.mode_time / s.bank_time, 1.0);
  float pitch_command =
      on_legs   ? pitch  // leaves the ground trimmed (step.cpp)
      : braking ? flare_pitch(s, b.pitch_trim, flare)
                : commanded_pitch(s, b.pitch_trim, e.y, b.position.y - ground, goal.y - ground);
  vec2 p = pitch_control(s, pitch_command, pitch, pitch_rate(b.attitude, b.omega));
  c.bend = p.x;
  c.sweep = p.y;

  c.omega = b.omega;
  c.circling = false;
  if (on_legs) {
    c.omega = vec3(0.0);
    return c;
  }
  float speed = c.steering.air_speed;  // a coordinated turn banks for the airspeed
  float turn_rate = sign_outside(c.steering.heading_error, s.dead_band) * s.turn_rate;
  float bank_cmd = 0.0;
  if (fixed_rate)
    bank_cmd = coordinated_bank(s, turn_rate, speed);
  else {
    float distance = length(goal.xz - b.position.xz);
    float circle = full_bank_radius(s, speed);
    c.circling = to_target && circles_goal(c.steering.heading_error_ahead, distance, circle, speed,
                                           goal.y - b.position.y, length(wind.xz));
    if (!(c.circling && b.circling > kCirclingTurn * 2.0 * kPi * circle / speed))  // step.cpp
      bank_cmd = heading_bank(s, c.steering.heading_error_ahead, distance, speed);
  }
  float most = min(ground_bank(s, b.position.y - pc.wind_ground.w),
                   recovery_bank(s, pitch, descent_angle(air_climb, airspeed), airspeed));
  bank_cmd = clamp(bank_cmd, -most, most);
  if (fixed_rate) {
    vec3 world_rate = rotate(b.attitude, c.omega);
    world_rate.y = -turn_rate;
    c.omega = rotate_back(b.attitude, world_rate);
  }
  c.omega.x = roll_for_bank(s, b.attitude, c.omega, bank, bank_cmd);
  return c;
}

// The step's forces as GpuForces (host_device.h): world frame, torques in the body frame. Only
// what is read survives compilation: the stepping loop keeps the total and the torque.
GpuForces forces(GpuBird b, GpuSpecies s, Commands c) {
  GpuForces f;
  vec3 body_air = rotate_back(b.attitude, step_wind - b.velocity);
  WingPoint right[2];
  right_wing_points(s, b.phase, b.amplitude, b.frequency, b.sweep, c.incidence, right[0], right[1]);
  // The aerodynamic forces are summed in the body frame and turned to the world once.
  precise vec3 body_force = vec3(0.0);
  precise vec3 torque = vec3(0.0);
  for (int i = 0; i < 2; ++i) {
    for (int side = 0; side < 2; ++side) {
      WingPoint p = side == 0 ? right[i] : mirror_to_left(right[i]);
      precise vec3 air = body_air - cross(c.omega, p.position) - p.velocity;
      vec3 force = aerodynamic_force(s, air, p.chord, p.normal, p.area);
      body_force += force;
      torque += cross(p.position, force);
      f.wing[2 * side + i] = vec4(rotate(b.attitude, force), 0.0);
    }
  }
  vec3 tail_position, tail_chord, tail_normal;
  tail_geometry(s, b.tail_bend, b.tail_twist, tail_position, tail_chord, tail_normal);
  precise vec3 tail_air = body_air - cross(c.omega, tail_position);
  vec3 tail =
      aerodynamic_force(s, tail_air, tail_chord, tail_normal, s.tail_area_per_radian * c.opening);
  vec3 tail_torque = cross(tail_position, tail);  // eq. 11
  f.tail = vec4(rotate(b.attitude, tail), 0.0);
  f.tail_torque = vec4(tail_torque, 0.0);
  f.torque = vec4(torque + tail_torque, 0.0);
  f.gravity = vec4(0.0, -s.mass * kGravity, 0.0, 0.0);
  f.ground = vec4(0.0);
  f.legs = vec4(0.0);
  precise vec3 total = rotate(b.attitude, body_force + tail);
  total.y -= s.mass * kGravity;
  if (pc.ground_effect != 0u) {
    float ground = ground_effect_force(s, b.position.y - pc.wind_ground.w);
    f.ground.y = ground;
    total.y += ground;
  }
  if (b.mode == mode_taking_off && b.mode_time >= s.crouch_time &&
      b.mode_time < s.crouch_time + s.leg_time) {
    vec3 ahead = normalize(horizontal(rotate(b.attitude, vec3(1, 0, 0))));
    vec3 legs = s.leg_force * (cos_p(s.push_angle) * ahead + sin_p(s.push_angle) * vec3(0, 1, 0));
    f.legs = vec4(legs, 0.0);
    total += legs;
  }
  f.total = vec4(total, 0.0);
  return f;
}

void stand_on_legs(inout GpuBird b, GpuSpecies s, float dt) {
  float crouch = min(b.mode_time / max(s.crouch_time, dt), 1.0);
  float floor_y = pc.wind_ground.w + s.stand_height - s.crouch_depth * crouch;
  if (b.mode_time < s.crouch_time) {
    b.velocity = vec3(0.0);
    b.position.y = floor_y;
  }
  if (b.position.y < floor_y) {
    b.position.y = floor_y;
    b.velocity.y = max(b.velocity.y, 0.0);
    if (b.mode_time < s.crouch_time + s.leg_time) b.velocity.xz = vec2(0.0);
  }
  b.omega = vec3(0.0);
}

GpuForces no_forces() {
  GpuForces f;
  f.wing[0] = f.wing[1] = f.wing[2] = f.wing[3] = vec4(0.0);
  f.tail = f.ground = f.legs = f.gravity = f.total = f.tail_torque = f.torque = vec4(0.0);
  return f;
}

// Whether a bird takes part in its flock now (flock.cpp).
bool flocks_now(GpuBird b) {
  return b.flocking != 0u && b.mode == mode_flying && b.landing_stage == stage_none;
}

// Whether every number of a bird's state is finite (bird.h: all_finite).
bool finite_number(float v) { return !isnan(v) && !isinf(v); }
bool finite_number(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }
bool finite_number(vec4 v) { return !any(isnan(v)) && !any(isinf(v)); }
bool finite_number(uint v) { return true; }
bool all_finite(GpuBird b) {
  return true
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) &&finite_number(b.name)
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
      ;
}

// One step of dt from `time`; returns the step's forces (zero for a bird at rest or quarantined).
// `seen`: its last perception (none seen: it flies its route alone). A step whose result is not
// finite is undone by the caller (step.glsl), which quarantines the bird.
GpuForces step_bird(inout GpuBird b, GpuSpecies s, inout Leg leg, float time, float dt,
                    GpuPerception seen) {
  if (b.mode == mode_quarantined) return no_forces();
  if (b.mode == mode_perched || (b.mode == mode_standing && time + 0.5 * dt < b.takeoff_time)) {
    b.mode_time += dt;
    return no_forces();
  }
  step_wind = wind_at(b.position.y);
  if (b.mode == mode_standing) {
    vec3 wind = step_wind;
    if (heeds_wind(s, length(wind.xz))) b.attitude = facing(-wind);  // step.cpp
    b.mode = mode_taking_off;
    b.mode_time = 0.0;
    b.frequency = s.f_max;
    b.amplitude = s.amp_max;
  }
  vec3 goal = route_goal(b, s, leg);
  if (approach_branch(b, s, leg)) return no_forces();
  float airspeed_command = b.airspeed;
  if (seen.neighbours > 0u && flocks_now(b)) {  // its social goal (step.cpp)
    goal = b.position + s.lookahead * seen.direction;
    airspeed_command = seen.airspeed;
  }
  Commands c = control(b, s, goal, way_to_perch(b, s, leg), airspeed_command);
  GpuForces f = forces(b, s, c);

  bool on_legs = b.mode == mode_taking_off;
  precise vec3 position = b.position + b.velocity * dt;
  precise vec3 velocity = b.velocity + f.total.xyz / s.mass * dt;
  precise vec3 omega =
      c.omega + f.torque.xyz * vec3(s.inv_inertia_x, s.inv_inertia_y, s.inv_inertia_z) * dt;
  b.position = position;
  b.velocity = velocity;
  b.attitude = integrate_attitude(b.attitude, c.omega, dt);
  b.omega = omega;
  if (on_legs) stand_on_legs(b, s, dt);

  b.phase = mod(b.phase + 2.0 * kPi * b.frequency * dt, 2.0 * kPi);
  b.frequency =
      on_legs ? s.f_max : rate_step(b.frequency, s.f_min, s.f_max, s.K_f, c.energy_error, dt);
  b.amplitude =
      on_legs ? s.amp_max : rate_step(b.amplitude, s.amp_min, s.amp_max, s.K_a, c.energy_error, dt);
  if (!on_legs)
    b.pitch_trim = clamp(b.pitch_trim + s.balance_gain * c.balance / s.trim_time * dt, s.pitch_min,
                         s.pitch_max);
  b.tail_bend = approach(b.tail_bend, c.bend, s.tail_rate, dt);
  b.tail_twist = approach(b.tail_twist, c.twist, s.tail_rate, dt);
  b.sweep = approach(b.sweep, c.sweep, s.sweep_rate, dt);
  b.mode_time += dt;
  b.circling = c.circling ? b.circling + dt : 0.0;
  if (on_legs && b.mode_time >= s.crouch_time + s.leg_time) {
    b.mode = mode_flying;
    b.mode_time = 0.0;
  }
  // The ground is solid: touch down, stand, take off again when rested (step.cpp).
  float ground = pc.wind_ground.w;
  if (!on_legs && b.position.y < ground + s.stand_height && b.velocity.y < 0.0) {
    come_to_rest(b, vec3(b.position.x, ground + s.stand_height, b.position.z));
    b.mode = mode_standing;
    b.takeoff_time = time + dt + kRestAfterTouchdown;
    b.landing_stage = stage_none;
  }
  return f;
}
