// engine/model/step.cpp in float (model.glsl), function for function in its order; the reasons
// are in the C++.

// bird.h: mode_time, count_mode_step, count_circling_step.
float mode_time(GpuBird b) { return float(b.mode_steps) * pc.dt; }
void count_mode_step(inout GpuBird b) {
  if (b.mode_steps < 0xffffffffu) ++b.mode_steps;
}
void count_circling_step(inout GpuBird b) {
  if (b.circling_steps < 0xffffffffu) ++b.circling_steps;
}

struct Commands {
  Steering steering;
  float energy_error;  // what eqs. 4, 5 follow, cm
  float balance;       // what the pitch trim integrates, cm
  float bend, twist;   // where the tail moves to
  float sweep;         // where the wings' sweep moves to
  float incidence;     // the arms' added incidence (braking)
  bool final;          // hovering onto the perch point (Species::hover_final)
  float hover;         // how much, in [0, 1] (control.h: hover_share)
  float amplitude;     // the wingbeat's amplitude this step (the final's answers at once)
  float opening;       // the tail's, eq. 10
  vec3 omega;          // the body rates this step, with the controller's kinematic ones
  bool circling;       // the goal lies inside the full-bank circle
};

// step.cpp's World is pc, step_wind and the bird's route: the route alone, not its Leg, which
// made glslang's precise propagation blow up (docs/ARCHITECTURE.md).
Commands control(GpuBird b, GpuSpecies s, GpuRoute route, vec3 goal, float airspeed_command,
                 bool in_air) {
  vec4 way = way_to_perch(b, s, route);
  float ground = pc.wind_ground.w + s.stand_height;
  // No bird flies lower than it stands, but one gliding down its path to its site on the ground.
  if (!(way.w >= 0.0 && lands_on_ground(s) && !in_air)) goal.y = max(goal.y, ground);
  bool on_legs = b.mode == mode_taking_off;
  bool braking = kBranches && b.mode == mode_landing;  // only a route's branch starts it
  bool final = braking && way.w >= 0.0 && hovers(s);
  float to_point = way.w >= 0.0 ? length(way.xz) : -1.0;
  if (final) {
    goal.y += final_aim(s, to_point);
    goal += final_track(s, way.xyz, b.velocity);
  } else if (braking)
    goal.y += kFlareAimAbove * s.perch_radius;
  else if (way.w >= 0.0 && hovers(s) && !in_air)
    goal.y += kApproachAbove * s.perch_radius;
  bool fixed_rate = pc.turning == 1u && !braking;
  float to_perch = way.w;  // -1: none
  vec3 wind = step_wind;
  Commands c;
  c.final = final;
  float ground_speed = final ? final_speed(s, to_perch, to_point) : approach_speed(s, to_perch);
  c.steering = steer_towards(s, b.attitude, b.position, b.velocity, goal, wind, ground_speed,
                             braking, airspeed_command > 0.0 && !on_legs, in_air);
  if (final && to_point < kHoldHeading * s.perch_radius && !heeds_wind(s, length(wind.xz))) {
    c.steering.heading_error = 0.0;  // heads on close by the point in calm air
    c.steering.heading_error_ahead = 0.0;
  }
  float bank = bank_angle(b.attitude);
  float pitch = pitch_angle(b.attitude);
  bool to_target = to_perch < 0.0 && b.landing_stage == stage_none;
  if (to_target && !fixed_rate) turn_on(s, bank, c.steering);
  c.twist = clamp(tail_twist_command(s, c.steering, fixed_rate), min(0.0, -s.tail_roll_max - bank),
                  max(0.0, s.tail_roll_max - bank));
  c.opening = tail_opening(s, b);

  float airspeed = length(b.velocity - wind);
  float air_climb = b.velocity.y - wind.y;
  float commanded = commanded_airspeed(s, airspeed_command, c.steering.aim_speed, to_perch >= 0.0);
  Energy e = energy_errors(s, c.steering.height_error, airspeed, commanded, b.position.y - ground,
                           goal.y - ground);
  c.energy_error = final     ? kFinalLead * (final_climb(goal.y - b.position.y,
                                                         final_aim_rate(s, way.xyz, b.velocity)) -
                                         b.velocity.y)
                   : braking ? c.steering.height_error
                             : e.total + spool_lead(s, b.amplitude, air_climb) +
                                   (in_air ? speed_lead_error(s, airspeed, b.airspeed_rate) : 0.0);
  if (!final && pitch > (braking ? s.brake_pitch : s.pitch_max) + kPitchOverrun)
    c.energy_error = min(c.energy_error, 0.0);
  if (pitch < s.pitch_min - kPitchOverrun) c.energy_error = max(c.energy_error, 1.0);
  c.balance = e.balance;
  float flare = braking && to_perch >= 0.0
                    ? flare_share(s, airspeed, perch_airspeed(s, way.xyz, wind), to_perch)
                    : 0.0;
  // The final hovers at a low airspeed, reading the ground velocity over the last wingbeat.
  vec2 beat_track = b.velocity.xz;
  if (final && length(beat_track) > 0.0) beat_track *= last_beat_speed(b) / length(b.velocity);
  float hover_airspeed = length(beat_track - wind.xz);
  c.hover = final ? hover_share(hover_airspeed) : 0.0;
  c.incidence = (1.0 - c.hover) * s.brake_incidence * flare * min(mode_time(b) / s.bank_time, 1.0);
  float hovering = 0.0;
  if (c.hover > 0.0) {
    vec2 head = rotate(b.attitude, vec3(1, 0, 0)).xz;
    vec2 along = length(head) > 0.0 ? head / length(head) : head;
    float wanted = dot(way.xz, along) < 0.0 ? -kFinalSpeed * s.touchdown_speed : ground_speed;
    float speed_along = dot(beat_track, along);
    hovering = hover_pitch(s, hover_airspeed, speed_along, wanted);
    c.incidence += c.hover * hover_incidence(s, speed_along, wanted);
  }
  float pitch_command =
      on_legs   ? pitch  // leaves the ground trimmed
      : braking ? c.hover * hovering + (1.0 - c.hover) * flare_pitch(s, b.pitch_trim, flare)
                : max(hovers(s) ? go_round_pitch(s, airspeed) : -kPi,
                      commanded_pitch(s, b.pitch_trim, e.balance, b.position.y - ground,
                                      goal.y - ground));
  PitchControl p = pitch_control(s, pitch_command, pitch,
                                 (1.0 - kHoverDamping * c.hover) * pitch_rate(b.attitude, b.omega));
  c.bend = p.bend;
  c.sweep = p.sweep;
  c.amplitude = final ? final_amplitude(s, b.amplitude, c.energy_error) : b.amplitude;

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
    if (!(c.circling &&
          float(b.circling_steps) * pc.dt > kCirclingTurn * 2.0 * kPi * circle / speed))
      bank_cmd = heading_bank(s, c.steering.heading_error_ahead, distance, speed,
                              c.hover > 0.5 ? 0.0 : s.dead_band);
  }
  float most = min(ground_bank(s, b.position.y - pc.wind_ground.w),
                   max(recovery_bank(s, pitch, descent_angle(air_climb, airspeed), airspeed),
                       c.hover * kHoverBank));
  bank_cmd = clamp(bank_cmd, -most, most);
  if (fixed_rate) {
    vec3 world_rate = rotate(b.attitude, c.omega);
    world_rate.y = -turn_rate;
    c.omega = rotate_back(b.attitude, world_rate);
  }
  c.omega.x = roll_for_bank(s, b.attitude, c.omega, bank_cmd);
  return c;
}

// flock.cpp: wake_now, the source in the bird's tile (`shift`).
GpuWakeSource wake_now(GpuWakeSource seen, uint seen_step, uint step, float dt, vec3 shift) {
  precise float since = float(step - seen_step) * dt;  // mod 2^32 steps
  GpuWakeSource w = seen;
  vec3 wind = wind_at(seen.position_phase.y);
  precise vec3 position =
      seen.position_phase.xyz + shift + (seen.air_velocity_frequency.xyz + wind) * since;
  precise float phase = seen.position_phase.w + 2.0 * kPi * seen.air_velocity_frequency.w * since;
  w.position_phase = vec4(position, phase);
  return w;
}

// step.cpp: wake_air, into `wing` (the four wing points) and `tail`, body frame.
void wake_air(GpuBird b, GpuSpecies s, GpuPerception seen, uint step, float dt, WingPoint right[2],
              vec3 tail_position, out vec3 wing[4], out vec3 tail) {
  vec3 at[5] = vec3[5](right[0].position, right[1].position, mirror_to_left(right[0]).position,
                       mirror_to_left(right[1]).position, tail_position);
  vec3 air[5] = vec3[5](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  vec3 shift = tile_shift(seen.wake_tile_x, seen.wake_tile_z, b.tile_x, b.tile_z);
  for (uint k = 0u; k < seen.wakes; ++k) {
    GpuWakeSource now = wake_now(seen.wake[k], seen.wake_step, step, dt, shift);
    for (int p = 0; p < 5; ++p) {
      precise vec3 point = b.position + rotate(b.attitude, at[p]);
      air[p] += rotate_back(b.attitude, wake_velocity(s, now, point));
    }
  }
  for (int p = 0; p < 4; ++p) wing[p] = air[p];
  tail = air[4];
}

// step.cpp: beat_frequency (formation flying shifts the phase only where wakes are met).
float beat_frequency(GpuBird b, GpuPerception seen, bool social) {
  precise float f = b.frequency + (kWakes && social ? seen.phase_rate / (2.0 * kPi) : 0.0);
  return f;
}

// The step's forces as GpuForces (host_device.h): world frame, torques in the body frame; with the
// wakes the bird meets (seen, at step `step`). Only what is read survives compilation: the
// stepping loop keeps the total and the torque.
GpuForces forces(GpuBird b, GpuSpecies s, Commands c, GpuPerception seen, bool social, uint step,
                 float dt) {
  GpuForces f;
  vec3 body_air = rotate_back(b.attitude, step_wind - b.velocity);
  WingPoint right[2];
  right_wing_points(s, b.phase, c.amplitude, beat_frequency(b, seen, social), b.sweep, c.incidence,
                    right);
  TailGeometry tg = tail_geometry(s, b.tail_bend, b.tail_twist);
  vec3 wake_wing[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  vec3 wake_tail = vec3(0.0);
  if (kWakes && social && seen.wakes > 0u)
    wake_air(b, s, seen, step, dt, right, tg.position, wake_wing, wake_tail);
  WingForces wings = wing_forces_at(s, right, body_air, c.omega, wake_wing);
  for (int i = 0; i < 4; ++i) f.wing[i] = vec4(rotate(b.attitude, wings.force[i]), 0.0);
  // The aerodynamic forces are summed in the body frame, in wing_forces' order (the arms, then
  // the hands), and turned to the world once.
  precise vec3 body_force = vec3(0.0);
  body_force += wings.force[0];
  body_force += wings.force[2];
  body_force += wings.force[1];
  body_force += wings.force[3];
  precise vec3 tail_air = body_air - cross(c.omega, tg.position);
  tail_air += wake_tail;
  vec3 tail = aerodynamic_force(s, tail_air, tg.chord, tg.normal, tail_area(s, c.opening));
  vec3 tail_torque = cross(tg.position, tail);  // eq. 11
  f.tail = vec4(rotate(b.attitude, tail), 0.0);
  // The wingbeat's aerodynamic power and the wakes' air at the wing points (step.cpp).
  WingPoint at[4] =
      WingPoint[4](right[0], right[1], mirror_to_left(right[0]), mirror_to_left(right[1]));
  precise float power = 0.0;
  for (int i = 0; i < 4; ++i) power -= dot(wings.force[i], at[i].velocity);
  precise vec3 wake_mean = (wake_wing[0] + wake_wing[1] + wake_wing[2] + wake_wing[3]) / 4.0;
  f.wake_air_power = vec4(rotate(b.attitude, wake_mean), power);
  f.tail_torque = vec4(tail_torque, 0.0);
  f.torque = vec4(wings.torque + tail_torque, 0.0);
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
  float in_mode = mode_time(b);
  if (b.mode == mode_taking_off && in_mode >= s.crouch_time &&
      in_mode < s.crouch_time + s.leg_time) {
    vec3 ahead = normalize(horizontal(rotate(b.attitude, vec3(1, 0, 0))));
    vec3 legs = s.leg_force * (cos_p(s.push_angle) * ahead + sin_p(s.push_angle) * vec3(0, 1, 0));
    f.legs = vec4(legs, 0.0);
    total += legs;
  }
  f.total = vec4(total, 0.0);
  return f;
}

void stand_on_legs(inout GpuBird b, GpuSpecies s, float dt) {
  float in_mode = mode_time(b);
  float crouch = min(in_mode / max(s.crouch_time, dt), 1.0);
  float floor_y = pc.wind_ground.w + s.stand_height - s.crouch_depth * crouch;
  if (in_mode < s.crouch_time) {
    b.velocity = vec3(0.0);
    b.position.y = floor_y;
  }
  if (b.position.y < floor_y) {
    b.position.y = floor_y;
    b.velocity.y = max(b.velocity.y, 0.0);
    if (in_mode < s.crouch_time + s.leg_time) b.velocity.xz = vec2(0.0);
  }
  b.omega = vec3(0.0);
}

GpuForces no_forces() {
  GpuForces f;
  f.wing[0] = f.wing[1] = f.wing[2] = f.wing[3] = vec4(0.0);
  f.tail = f.ground = f.legs = f.gravity = f.total = f.tail_torque = f.torque = vec4(0.0);
  f.wake_air_power = vec4(0.0);
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
bool finite_number(uvec2 v) { return true; }
bool all_finite(GpuBird b) {
  return true
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) &&finite_number(b.name)
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
      ;
}

// step.cpp: settle.
void settle(inout GpuBird b, GpuSpecies s, float dt) {
  vec3 off = b.position - b.via_point;
  precise vec3 pull = -kSettleStiffness * off - 2.0 * sqrt(kSettleStiffness) * b.velocity;
  float strength = length(pull);
  if (strength > kSettleDecel) pull *= kSettleDecel / strength;
  precise vec3 velocity = b.velocity + pull * dt;
  precise vec3 position = b.position + velocity * dt;
  b.velocity = velocity;
  b.position = position;
  float floor_y = pc.wind_ground.w + min(0.5 * s.box_b, s.stand_height);  // its body on the ground
  bool on_ground = lands_on_ground(s) && b.via_point.y <= pc.wind_ground.w + s.stand_height;
  if ((b.mode == mode_standing || on_ground) && b.position.y < floor_y) {
    b.position.y = floor_y;
    b.velocity.y = max(b.velocity.y, 0.0);
  }
  vec4 level = level_attitude(b.attitude);
  b.attitude = turn_towards(b.attitude, level, kSettleTurn * dt);
  b.omega = vec3(0.0);
  b.phase = mod(b.phase + 2.0 * kPi * b.frequency * dt, 2.0 * kPi);
  b.amplitude = approach(b.amplitude, 0.0, s.amp_max / kWingFold, dt);
  b.tail_bend = approach(b.tail_bend, 0.0, s.tail_rate, dt);
  b.tail_twist = approach(b.tail_twist, 0.0, s.tail_rate, dt);
  b.sweep = approach(b.sweep, 0.0, s.sweep_rate, dt);
  if (length(b.position - b.via_point) < kSettledDistance && length(b.velocity) < kSettledSpeed &&
      b.amplitude == 0.0 && turn_angle(b.attitude, level) < kSettledAngle) {
    come_to_rest(b, b.via_point);
    b.landing_stage = stage_none;
  }
}

// step.cpp: touch_down.
void touch_down(inout GpuBird b, GpuSpecies s, GpuRoute r) {
  vec3 level = horizontal(b.velocity);
  vec3 run = b.position + level * (length(level) / (2.0 * kSettleDecel));
  vec3 stop = vec3(run.x, pc.wind_ground.w + s.stand_height, run.z);
  if (at_landing_site(b, s, r, b.position)) {
    hold_on(b, mode_perched, stop);
    b.targets_reached += 1u;
    return;
  }
  hold_on(b, mode_standing, stop);
  b.rest_steps = pc.rest_steps;
}

// step.cpp: time_the_beat.
void time_the_beat(inout GpuBird b, float phase_before, float beat, bool on_legs, bool hovers,
                   float dt) {
  if (on_legs) {
    b.beat_airspeed = 0.0;
    b.airspeed_rate = 0.0;
    b.beat_path = 0.0;
    b.beat_speed = 0.0;
    return;
  }
  if (hovers) {
    precise float path = b.beat_path + length(b.velocity) * dt;
    b.beat_path = path;
  }
  if (b.phase < phase_before) {
    float airspeed = length(b.velocity - wind_at(b.position.y));
    if (b.beat_airspeed > 0.0) {
      precise float rate = (airspeed - b.beat_airspeed) * beat;
      b.airspeed_rate = rate;
    }
    b.beat_airspeed = airspeed;
    precise float mean = b.beat_path * beat;
    b.beat_speed = mean;
    b.beat_path = 0.0;
  }
}

// step.cpp: face_the_wind (`wind` where the bird stands).
bool face_the_wind(inout GpuBird b, GpuSpecies s, vec3 wind, float most) {
  if (!heeds_wind(s, length(wind.xz))) return true;
  vec4 into = facing(-wind);
  b.attitude = turn_towards(b.attitude, into, most);
  return b.attitude == into;  // turn_towards returns `into` itself once within `most`
}

// step.cpp's step_bird and advance: one step of dt; returns the step's forces (zero for
// a bird at rest or quarantined). `seen`: its last perception (none seen: it flies its route
// alone). A step whose result is not finite is undone by the caller (step.glsl), which quarantines
// the bird.
GpuForces step_bird(inout GpuBird b, GpuSpecies s, inout Leg leg, float dt, GpuPerception seen,
                    uint step) {
  if (b.mode == mode_quarantined) return no_forces();
  if (b.landing_stage == stage_settling) {
    settle(b, s, dt);
    if (b.mode == mode_standing && b.rest_steps > 0u) --b.rest_steps;
    count_mode_step(b);
    return no_forces();
  }
  if (b.mode == mode_perched) {
    count_mode_step(b);
    return no_forces();
  }
  step_wind = wind_at(b.position.y);
  if (b.mode == mode_standing) {
    bool into_wind = face_the_wind(b, s, step_wind, kSettleTurn * dt);
    if (b.rest_steps > 0u || !into_wind) {
      if (b.rest_steps > 0u) --b.rest_steps;
      count_mode_step(b);
      return no_forces();
    }
    b.mode = mode_taking_off;
    b.mode_steps = 0u;
    b.frequency = s.f_max;
    b.amplitude = s.amp_max;
  }
  vec3 goal = route_goal(b, s, leg);
  if (approach_branch(b, s, leg.route)) return no_forces();
  float airspeed_command = b.airspeed;
  bool social = seen.neighbours > 0u && flocks_now(b);
  if (social) {  // its social goal: a heading through the air
    goal = b.position + s.lookahead * seen.direction;
    airspeed_command = seen.airspeed;
  }
  Commands c = control(b, s, leg.route, goal, airspeed_command, social);
  GpuForces f = forces(b, s, c, seen, social, step, dt);

  bool on_legs = b.mode == mode_taking_off;
  if (kWakes && (b.flocking & kFeelsWakes) != 0u && !on_legs) {  // its lift (step.cpp)
    precise vec3 air = b.velocity - step_wind;
    precise vec3 wing = f.wing[0].xyz + f.wing[1].xyz + f.wing[2].xyz + f.wing[3].xyz;
    precise float air2 = dot(air, air);
    precise vec3 lift = air2 > 0.0 ? wing - air * (dot(wing, air) / air2) : wing;
    precise float lift_now = b.lift + (length(lift) - b.lift) * min(b.frequency * dt, 1.0);
    b.lift = lift_now;
  }
  precise vec3 position = b.position + b.velocity * dt;
  precise vec3 velocity = b.velocity + f.total.xyz / s.mass * dt;
  precise vec3 omega = c.omega + angular_acceleration(box_inertia(s), f.torque.xyz) * dt;
  b.position = position;
  b.velocity = velocity;
  b.attitude = integrate_attitude(b.attitude, c.omega, dt);
  b.omega = omega;
  if (on_legs) stand_on_legs(b, s, dt);

  float phase_before = b.phase, beat = beat_frequency(b, seen, social);
  b.phase = mod(b.phase + 2.0 * kPi * beat * dt, 2.0 * kPi);
  time_the_beat(b, phase_before, beat, on_legs, hovers(s), dt);
  if (c.final) {
    float frequency = b.frequency, amplitude = b.amplitude;
    final_wingbeat(s, c.energy_error, c.amplitude, c.hover, frequency, amplitude, dt);
    b.frequency = frequency;
    b.amplitude = amplitude;
  } else {
    b.frequency = on_legs ? s.f_max : frequency_step(s, b.frequency, c.energy_error, dt);
    b.amplitude = on_legs ? s.amp_max : amplitude_step(s, b.amplitude, c.energy_error, dt);
  }
  if (!on_legs)
    b.pitch_trim = clamp(b.pitch_trim + s.balance_gain * c.balance / s.trim_time * dt, s.pitch_min,
                         s.pitch_max);
  b.tail_bend = approach(b.tail_bend, c.bend, s.tail_rate, dt);
  b.tail_twist = approach(b.tail_twist, c.twist, s.tail_rate, dt);
  b.sweep = approach(b.sweep, c.sweep, s.sweep_rate, dt);
  count_mode_step(b);
  if (c.circling)
    count_circling_step(b);
  else
    b.circling_steps = 0u;
  if (on_legs && mode_time(b) >= s.crouch_time + s.leg_time) {
    b.mode = mode_flying;
    b.mode_steps = 0u;
  }
  // The ground is solid: touch down, stand, take off again when rested.
  float ground = pc.wind_ground.w;
  if (!on_legs && b.position.y < ground + s.stand_height && b.velocity.y < 0.0) {
    touch_down(b, s, leg.route);
  }
  return f;
}
