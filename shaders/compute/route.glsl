// engine/model/route.cpp in float (model.glsl), function for function in its order; the reasons
// are in the C++. Where C++ is handed the World, these are handed the bird's route (GpuRoute) or
// its Leg, and read the branches from their buffer.

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

// The branch the route has brought the bird to, as GpuRoute::branch: its index + 1, 0: none.
// Without branches in the scenario (kBranches) the landing's code folds away.
uint route_branch(GpuBird b, GpuRoute r) {
  return !kBranches || b.target < r.count ? 0u : r.branch;
}

vec3 perch_point(GpuBird b, GpuSpecies s, uint branch);  // declared ahead (route.h)

bool into_wind(GpuSpecies s, vec3 across, vec3 wind) {
  return heeds_wind(s, abs(dot(wind, across)));
}

vec3 landing_gate(GpuSpecies s, vec3 across, vec3 q2, float side) {
  return q2 + across * (side * kGateApproaches * s.approach_distance);
}

bool flown_past(GpuBird b, GpuSpecies s, vec3 to_perch) {
  return dot(to_perch.xz, b.velocity.xz) <= 0.0 && length(to_perch.xz) > s.perch_radius;
}

bool sunk_under(GpuBird b, GpuSpecies s, vec3 to_perch) {
  return to_perch.y > kSunkPerchRadii * s.perch_radius &&
         b.velocity.y < -kSunkTouchdowns * s.touchdown_speed;
}

// landing_goal's place_curve.
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
  float side = dot(windward ? wind : b.position - q2, across) < 0.0 ? -1.0 : 1.0;
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
  return vec3(on_curve.x, q2.y, on_curve.z);  // at the perch's height
}

void perch(inout GpuBird b, GpuSpecies s, uint branch) {
  hold_on(b, mode_perched, perch_point(b, s, branch));
  b.targets_reached += 1u;
}

// From the bird's tile (host_device.h: tile_shift).
vec3 perch_point(GpuBird b, GpuSpecies s, uint branch) {
  GpuBranch br = branches[branch];
  return br.point.xyz + tile_shift(br.tile_x, br.tile_z, b.tile_x, b.tile_z) +
         vec3(0.0, s.stand_height, 0.0);
}

// route.cpp: route_over, onward_goal.
bool route_over(GpuBird b, Leg leg) {
  return b.target >= leg.route.count && leg.route.branch == 0u;
}

bool onward_goal(GpuBird b, Leg leg, out vec3 goal) {
  goal = vec3(0.0);
  if (!route_over(b, leg) || leg.route.count < 2u) return false;
  GpuTarget last =
      targets[leg.targets_from + route_targets[leg.route.first + leg.route.count - 1u]];
  GpuTarget before =
      targets[leg.targets_from + route_targets[leg.route.first + leg.route.count - 2u]];
  vec3 l = last.centre_radius.xyz + tile_shift(last.tile_x, last.tile_z, b.tile_x, b.tile_z);
  vec3 p = before.centre_radius.xyz + tile_shift(before.tile_x, before.tile_z, b.tile_x, b.tile_z);
  goal = b.position + horizontal(l - p);
  goal.y = l.y;
  return true;
}

// route.cpp: lands_on_ground, glide_goal, at_landing_site.
bool lands_on_ground(GpuSpecies s) { return s.perches == 0.0; }

vec3 glide_goal(GpuBird b, GpuSpecies s, uint branch, vec3 goal, vec3 wind) {
  vec3 site = perch_point(b, s, branch);
  float slope = tan(kGlideSlope);
  if (b.landing_stage == stage_gate) {
    goal.y = site.y + slope * length(horizontal(goal - site));
    return goal;
  }
  vec3 ground_velocity = horizontal(b.velocity);
  float speed = length(ground_velocity);
  if (!(speed > 0.0)) return goal;
  vec3 way = horizontal(site - b.position);
  float along = dot(way, ground_velocity) / speed;
  bool near = length(way) <= s.perch_radius;
  float ahead = near ? along : length(way);
  if (near && along <= 0.0) {
    vec3 air = horizontal(b.velocity - wind);
    goal = b.position +
           (length(air) > 0.0 ? air / length(air) : ground_velocity / speed) * s.approach_distance;
  }
  goal.y = site.y + slope * (ahead - s.height_lead * speed);
  return goal;
}

bool at_landing_site(GpuBird b, GpuSpecies s, GpuRoute r, vec3 at) {
  uint br = route_branch(b, r);
  return br != 0u && lands_on_ground(s) &&
         length(horizontal(at - perch_point(b, s, br - 1u))) <= s.perch_radius;
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
  vec3 goal = (r.flags & kRoutePathControl) != 0u ? landing_goal(b, s, branch, step_wind)
                                                  : perch_point(b, s, branch);
  return lands_on_ground(s) ? glide_goal(b, s, branch, goal, step_wind) : goal;
}

// xyz: the way to where the bird perches, w: its length, once the perch is its goal; w -1 before
// (on its way to the landing gate too), or without a branch.
vec4 way_to_perch(GpuBird b, GpuSpecies s, GpuRoute r) {
  uint br = route_branch(b, r);
  if (br == 0u || b.landing_stage == stage_gate) return vec4(0.0, 0.0, 0.0, -1.0);
  vec3 way = perch_point(b, s, br - 1u) - b.position;
  return vec4(way, length(way));
}

float last_beat_speed(GpuBird b) {
  if (!(b.frequency > 0.0)) return length(b.velocity);
  float period = 1.0 / b.frequency;
  float window = max(period, kTouchdownWindow);
  float into = min(b.phase / (2.0 * kPi) * period, period);
  return (b.beat_path + b.beat_speed * (window - into)) / window;
}

bool braking_due(GpuSpecies s, GpuBird b, vec3 to_perch, vec3 wind, float distance) {
  return flare_share(s, length(b.velocity - wind), perch_airspeed(s, to_perch, wind), distance) >=
         kBrakeShare;
}

bool approach_branch(inout GpuBird b, GpuSpecies s, GpuRoute r) {
  uint br = route_branch(b, r);
  if (br == 0u || lands_on_ground(s)) return false;  // no braking: it touches down
  uint branch = br - 1u;
  vec3 to_perch = perch_point(b, s, branch) - b.position;
  float d = length(to_perch);
  bool grips = hovers(s)
                   ? d <= kGripReach * s.stand_height && last_beat_speed(b) <= s.touchdown_speed
                   : d <= s.perch_radius && length(b.velocity) <= s.touchdown_speed;
  if (grips) {
    perch(b, s, branch);
    return true;
  }
  bool closing = dot(to_perch.xz, b.velocity.xz) > 0.0;  // heading in horizontally
  if (b.mode == mode_landing && (flown_past(b, s, to_perch) || sunk_under(b, s, to_perch))) {
    b.mode = mode_flying;
    b.mode_steps = 0u;
    b.landing_stage = stage_none;
  } else if (b.mode == mode_flying && closing && b.landing_stage != stage_gate &&
             (d <= (hovers(s) ? kHoverBrakeDistances : 1.0) * s.brake_distance ||
              braking_due(s, b, to_perch, step_wind, d))) {
    b.mode = mode_landing;
    b.mode_steps = 0u;
  }
  return false;
}
