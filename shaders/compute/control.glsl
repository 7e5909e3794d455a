// engine/model/control.cpp in float (model.glsl), function for function in its order; the
// reasons are in the C++.

// control.h: Steering, Energy, PitchControl.
struct Steering {
  float heading_error, heading_error_ahead, height_error;
  float aim_speed;  // |crab_aim|
  float air_speed;  // horizontal, through the air
};
struct Energy {
  float total, balance;
};
struct PitchControl {
  float bend, sweep;
};

float sign_outside(float x, float band) { return x > band ? 1.0 : (x < -band ? -1.0 : 0.0); }

void turn_on(GpuSpecies s, float bank, inout Steering st) {
  if (abs(bank) <= 0.5 * s.bank_max || abs(st.heading_error) <= kBehind) return;
  float turn = bank > 0.0 ? 1.0 : -1.0;
  if (st.heading_error * turn > 0.0) return;
  st.heading_error += turn * 2.0 * kPi;
  st.heading_error_ahead += turn * 2.0 * kPi;
}

float steer_share(GpuSpecies s, float heading_error) {
  if (abs(heading_error) <= s.dead_band) return 0.0;
  return clamp(heading_error / s.steer_full_error, -1.0, 1.0);
}

vec3 crab_aim(vec3 to_goal, vec3 wind, float ground_speed) {
  vec3 way = horizontal(to_goal);
  float len = length(way);
  if (len == 0.0) return way;
  return way * (ground_speed / len) - horizontal(wind);
}

vec3 track_aim(vec3 to_goal, vec3 wind, float airspeed) {
  vec3 way = horizontal(to_goal);
  float len = length(way);
  if (len == 0.0 || airspeed <= 0.0) return -horizontal(wind);
  vec3 along = way / len;
  vec3 w = horizontal(wind);
  vec3 across = w - along * dot(along, w);
  float across_speed = length(across);
  if (across_speed >= airspeed) return across * (-airspeed / across_speed);
  return along * sqrt(airspeed * airspeed - across_speed * across_speed) - across;
}

// control.cpp: compensated_aim.
vec3 compensated_aim(vec3 to_goal, vec3 aim, float compensation) {
  vec3 way = horizontal(to_goal);
  if (compensation >= 1.0 || length(way) == 0.0 || length(aim) == 0.0) return aim;
  float crab = atan_p(way.x * aim.z - way.z * aim.x, way.x * aim.x + way.z * aim.z);
  float a = compensation * crab;
  return vec3(way.x * cos_p(a) - way.z * sin_p(a), 0.0, way.x * sin_p(a) + way.z * cos_p(a));
}

float approach_speed(GpuSpecies s, float to_branch) {
  if (to_branch < 0.0) return s.cruise_speed;
  float room = max(0.0, to_branch - s.perch_radius);
  return min(s.cruise_speed,
             sqrt(s.touchdown_speed * s.touchdown_speed + 2.0 * s.brake_decel * room));
}

Steering steer_towards(GpuSpecies s, vec4 attitude, vec3 position, vec3 velocity, vec3 goal,
                       vec3 wind, float ground_speed, bool by_course, bool commanded, bool in_air) {
  vec3 air = velocity - wind;
  float air_speed = length(air.xz);
  vec3 head = by_course && air_speed > kSteerAirspeed ? air : rotate(attitude, vec3(1, 0, 0));
  vec3 to_goal = goal - position;
  vec3 aim = crab_aim(to_goal, wind, ground_speed);
  float aim_speed = length(aim);
  vec3 head_for = aim;
  if (in_air)
    head_for = horizontal(to_goal);
  else if (!by_course)
    head_for = compensated_aim(
        to_goal, commanded || air_speed > aim_speed ? track_aim(to_goal, wind, air_speed) : aim,
        s.drift_compensation);
  float heading_error =
      atan_p(-head.z * head_for.x + head.x * head_for.z, head.x * head_for.x + head.z * head_for.z);
  float turn_rate = air_speed > 1.0 ? kGravity * tan_p(bank_angle(attitude)) / air_speed : 0.0;
  return Steering(heading_error, heading_error - s.heading_lead * turn_rate,
                  to_goal.y - s.height_lead * velocity.y, aim_speed, air_speed);
}

float rate_step(float value, float lo, float hi, float rate, float dy, float dt) {
  return clamp(value + sign(dy) * rate * dt, lo, hi);
}

float frequency_step(GpuSpecies s, float frequency, float dy, float dt) {  // eq. 4
  return rate_step(frequency, s.f_min, s.f_max, s.K_f, dy, dt);
}

float amplitude_step(GpuSpecies s, float amplitude, float dy, float dt) {  // eq. 5
  return rate_step(amplitude, s.amp_min, s.amp_max, s.K_a, dy, dt);
}

float tail_twist_command(GpuSpecies s, Steering st, bool fixed_rate) {
  return steer_share(s, fixed_rate ? st.heading_error : st.heading_error_ahead) * s.rot_max;
}

float commanded_airspeed(GpuSpecies s, float command, float aim_speed, bool to_branch) {
  if (to_branch) return clamp(aim_speed, s.min_speed, s.max_speed);
  if (command > 0.0) return clamp(command, s.min_speed, s.max_speed);
  return clamp(aim_speed, s.cruise_speed, s.max_speed);
}

float clearance_floor(GpuSpecies s, float goal_height) { return min(s.clearance, goal_height); }

Energy energy_errors(GpuSpecies s, float height_error, float airspeed, float commanded,
                     float height, float goal_height) {
  float room = goal_height > height ? max(height - clearance_floor(s, goal_height), 0.0) : 3.4e38;
  precise float deficit = (commanded * commanded - airspeed * airspeed) / (2.0 * kGravity);
  float height_share =
      clamp((airspeed / s.min_speed - kSpeedFirst) / (1.0 - kSpeedFirst), 0.0, 1.0);
  return Energy(
      height_error + deficit,
      height_share * clamp(height_error, -s.balance_band, s.balance_band) - min(deficit, room));
}

float spool_lead(GpuSpecies s, float amplitude, float air_climb) {
  if (s.K_a <= 0.0 || air_climb >= 0.0) return 0.0;
  return 0.5 * (s.amp_max - amplitude) / s.K_a * -air_climb;
}

// control.cpp: speed_lead_error.
float speed_lead_error(GpuSpecies s, float airspeed, float airspeed_rate) {
  return -s.speed_lead * airspeed * airspeed_rate / kGravity;
}

float commanded_pitch(GpuSpecies s, float pitch_trim, float balance, float height,
                      float goal_height) {
  float pitch = clamp(pitch_trim + s.balance_gain * balance, s.pitch_min, s.pitch_max);
  float floor_height = clearance_floor(s, goal_height);
  if (height >= floor_height) return pitch;
  return max(pitch, s.climb_pitch * (1.0 - height / floor_height));
}

bool heeds_wind(GpuSpecies s, float speed) { return speed > kTouchdownAim * s.touchdown_speed; }

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

// control.h: the hovering final.
bool hovers(GpuSpecies s) { return s.hover_final != 0.0; }

float final_share(GpuSpecies s, float to_point) {
  return (to_point / s.perch_radius - kFinalTo) / (kFinalFrom - kFinalTo);
}

float final_aim(GpuSpecies s, float to_point) {
  float u = clamp(final_share(s, to_point), 0.0, 1.0);
  return s.perch_radius * (kEndAbove + (kApproachAbove - kEndAbove) * u * u * (3.0 - 2.0 * u));
}

vec3 final_track(GpuSpecies s, vec3 way, vec3 velocity) {
  float d = length(way.xz);
  // Within kHoldHeading radii it heads on (in a wind, for the point itself); the aim fades in over
  // the next kHoldHeading radii out.
  float hold = kHoldHeading * s.perch_radius;
  float fade = clamp((d - hold) / hold, 0.0, 1.0);
  if (!(s.final_track_lead > 0.0 && fade > 0.0)) return vec3(0.0);
  vec3 to = horizontal(way) / d;
  vec3 across = horizontal(velocity) - to * dot(horizontal(velocity), to);
  return -across * fade * min(s.final_track_lead, d / max(length(velocity.xz), 1.0));
}

float final_aim_rate(GpuSpecies s, vec3 way, vec3 velocity) {
  float d = length(way.xz);
  float u = final_share(s, d);
  if (!(u > 0.0 && u < 1.0)) return 0.0;
  float closing = dot(way.xz, velocity.xz) / d;
  return -(kApproachAbove - kEndAbove) * 6.0 * u * (1.0 - u) / (kFinalFrom - kFinalTo) * closing;
}

float final_speed(GpuSpecies s, float to_perch, float to_point) {
  float end = kFinalSpeed * s.touchdown_speed;
  return min(approach_speed(s, to_perch),
             sqrt(end * end + 2.0 * kFinalDecel * s.brake_decel * to_point));
}

float final_climb(float height_error, float aim_rate) {
  float sink = sqrt(2.0 * kFinalSinkDecel * max(-height_error, 0.0));
  return clamp(kFinalClimbGain * height_error, -sink, kFinalClimbMax) + aim_rate;
}

float hover_share(float airspeed) {
  return clamp((kHoverAirspeed - airspeed) / kHoverBand, 0.0, 1.0);
}

float hover_pitch(GpuSpecies s, float airspeed, float along, float wanted) {
  float up = min(atan_p(kHoverLift / (airspeed + kHoverLiftSpeed)), kHoverBasePitch);
  return clamp(up + kHoverPitchGain * (along - wanted), 0.0, s.hover_pitch_max);
}

float hover_incidence(GpuSpecies s, float along, float wanted) {
  if (!(s.hover_incidence > 0.0)) return 0.0;
  return clamp(s.hover_incidence + kHoverIncidenceGain * (along - wanted), 0.0, kHoverIncidenceMax);
}

float final_amplitude(GpuSpecies s, float amplitude, float energy_error) {
  return clamp(amplitude + kFinalAmplitudeGain * energy_error, s.amp_min, s.amp_max);
}

void final_wingbeat(GpuSpecies s, float energy_error, float used, float hover,
                    inout float frequency, inout float amplitude, float dt) {
  float share = clamp(energy_error / (kFinalBand * s.perch_radius), -1.0, 1.0);
  amplitude = clamp(amplitude + kFinalAmplitudeRate * s.K_a * share * dt, s.amp_min, s.amp_max);
  float range = s.amp_max - s.amp_min;
  float trim = clamp((used - s.amp_min - kFinalTrimLow * range) / (0.1 * range), -1.0, 1.0);
  // At full amplitude and still short of its climb, a bird that may (final_beats_faster) quickens.
  bool quickens = s.final_beats_faster != 0.0 && used >= s.amp_max && share > 0.0;
  float rate = hover > 0.5 || quickens ? kFinalFrequencyRate : kFinalTrimRate * trim;
  frequency = clamp(frequency + rate * s.K_f * dt, s.f_min, s.f_max);
}

float go_round_pitch(GpuSpecies s, float airspeed) {
  float share = 1.0 - airspeed / (0.5 * s.min_speed);
  return share > 0.0 ? s.brake_pitch * min(share, 1.0) : -kPi;
}

PitchControl pitch_control(GpuSpecies s, float pitch_command, float pitch, float rate) {
  float error = pitch_command - pitch - s.pitch_damping * rate;
  float beyond = error - clamp(error, -s.pitch_band, s.pitch_band);
  return PitchControl(clamp(s.pitch_gain * beyond, -s.bend_max, s.bend_max),
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

float roll_for_bank(GpuSpecies s, vec4 attitude, vec3 omega, float bank_command) {
  float wanted = (bank_command - bank_angle(attitude)) / s.bank_time;
  float per_roll = bank_rate(attitude, vec3(1, 0, 0));
  float roll = abs(per_roll) > 0.1
                   ? (wanted - bank_rate(attitude, vec3(0.0, omega.y, omega.z))) / per_roll
                   : wanted;
  return clamp(roll, -s.roll_rate, s.roll_rate);
}

float approach(float angle, float command, float rate, float dt) {
  float step = rate * dt;
  return angle + clamp(command - angle, -step, step);
}

float full_bank_radius(GpuSpecies s, float speed) {
  return kWideTurn * speed * speed / (kGravity * s.tan_bank_max);
}

bool circles_goal(float heading_error, float distance, float radius, float speed, float rise,
                  float wind) {
  if (2.0 * kPi * wind >= speed) return false;
  return abs(rise) < kLevelGoal * distance && distance < 2.0 * radius * abs(sin_p(heading_error));
}

float coordinated_bank(GpuSpecies s, float turn_rate, float speed);  // declared ahead (control.h)
float heading_bank(GpuSpecies s, float heading_error, float distance, float speed,
                   float dead_band) {
  if (abs(heading_error) <= dead_band) return 0.0;
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

float coordinated_bank(GpuSpecies s, float turn_rate, float speed) {
  return clamp(atan_p(speed * turn_rate / kGravity), -s.bank_max, s.bank_max);
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
