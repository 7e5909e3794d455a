// Flocking (engine/model/flock.cpp, the same in float): what a bird sees, its k nearest by a
// search of the neighbour grid's cells nearest first, and its social goal. The includer declares
// the grid's texel buffers, the ids and kSeen, and includes model.glsl first (perceive.comp).

float square(float x) { return x * x; }  // std::pow(x, 2.0), exactly; GLSL's pow is not

vec3 unit_or_zero(vec3 v) {
  float l = length(v);
  return l > 0.0 ? v / l : vec3(0.0);
}

// flock.cpp: flight_direction, through the air moving with `wind`.
vec3 flight_direction(GpuBird b, vec3 wind) {
  vec3 air = b.velocity - wind;
  return length(air) > 0.0 ? normalize(air) : rotate(b.attitude, vec3(1, 0, 0));
}

// Outside the blind sector (flock.cpp: outside_blind): `cos_blind` = cos(blind_angle / 2).
bool outside_blind(vec3 ahead, vec3 offset, float distance2, float cos_blind) {
  return -dot(offset, ahead) <= cos_blind * sqrt(distance2);
}

// Its k nearest are sought all round, the blind sector hiding them from all but the separation
// (flock.cpp: sees, social_goal).
bool all_round(GpuSpecies s) { return s.separation_all_round != 0.0; }

// The k nearest found (search), nearest first, ties by index, for the social goal.
uint near_index[kMaxNeighbours];
float near_d2[kMaxNeighbours];
uint near_count;
// Set when a loop of the search ended before its end (a driver's limit on a shader's loops): every
// loop below ends by its own condition otherwise, and the probing one at the cell or an empty slot.
bool search_cut;

const float kFar = 3.4e38;  // an empty place's distance squared: every bird seen is nearer

// Nearer, ties by index (flock.cpp: Nearest). The indices compared as ints, which a CPU device
// compares in one instruction where it takes three for uints: birds are fewer than 2^31, and
// kNoBird's tie is with kFar alone, which no bird seen is as far as.
bool nearer(float d2, uint j, float than_d2, uint than_j) {
  return d2 < than_d2 || (d2 == than_d2 && int(j) < int(than_j));
}

// grid_cells.comp's lattice steps of a place, from their word.
uvec3 unpack_steps(uint w) { return uvec3(w, w >> 10u, w >> 20u) & 1023u; }

// The distance squared from `inside` to the box from `low` to `high`: 0 inside it.
float gap2_to_box(vec3 low, vec3 high, vec3 inside) {
  vec3 below = low - inside, above = inside - high;  // one at most is above 0: low <= high
  vec3 gap = mix(vec3(0.0), below, greaterThan(below, vec3(0.0))) +
             mix(vec3(0.0), above, greaterThan(above, vec3(0.0)));
  return dot(gap, gap);
}

// The range of the sorted birds in cell c of a flock (xy), empty when no bird of it is there, and
// the bounds of their places (zw, grid_cells.comp). Its search in the table starts at its slot
// (grid.glsl): a slot holding the cell, or an empty one, ends it. A slot holding another cell means
// the cell, if it is anywhere, is further on: with `probing` the search goes on (grid_probe_step),
// without it `blocked` is set (a CPU device would run the probing loop's body for every cell,
// though a compact flock never needs it).
bool holds_another(ivec4 key, ivec3 c, uint flock) {
  return key.w != kNoFlock && (key.w != int(flock) || key.xyz != c);
}

uvec4 cell_birds(ivec3 c, uint flock, bool probing, inout bool blocked) {
  uint slot = grid_slot(c, flock);
  ivec4 key = imageLoad(grid_keys, int(slot));
  bool other = holds_another(key, c, flock);
  if (probing) {
    uint step = grid_probe_step(c, flock, pc.buckets);
    while (other) {
      slot = (slot + step) & (pc.buckets - 1u);
      key = imageLoad(grid_keys, int(slot));
      other = holds_another(key, c, flock);
    }
    if (other) search_cut = true;
  } else if (other) {
    blocked = true;
  }
  return key.w == kNoFlock || other ? uvec4(0u) : imageLoad(grid_cells, int(slot));
}

// Bird i's k nearest seen birds of its flock (flock.cpp: NeighbourGrid::seen_by finds the same),
// in the frame of its cell's low corner: cells and places in them are exact (grid.glsl), so the
// offsets between birds are as fine 1,000 km out as at the origin.
//
// Written for a CPU device's lanes as much as for a GPU: where the invocations diverge, a CPU
// device (lavapipe) runs every branch under a mask and a loop's body once more than its longest
// lane, so it is the loops' trips that cost. The cells are searched nearest first, in the order
// made for the part of its cell the bird is in (flock.h: grid_search_order), and a bird stops at
// the first cell that cannot hold a nearer bird than its k-th: few cells are searched in vain. The
// k nearest stay in registers (constant indices, kSeen of them), a bird moving down them without a
// branch. The grid is read as texels, loaded for all lanes at once.
//
// Without `probing` the search gives up, returning true, at the first cell whose slot holds
// another (cell_birds); it is then run again with it.
bool search(uint i, GpuBird b, GpuSpecies s, uint k, bool probing) {
  float kept_d2[kMaxNeighbours];
  uint kept[kMaxNeighbours];
  [[unroll]] for (uint n = 0u; n < kSeen; ++n) {
    kept_d2[n] = kFar;
    kept[n] = kNoBird;
  }
  float worst_d2 = kFar;  // the k-th kept: a bird must be nearer to be kept
  uint worst = kNoBird;
  vec3 ahead = flight_direction(b, step_wind);
  float cell = pc.grid_cell;
  vec3 inside;
  ivec3 home = grid_cell(b, cell, inside);
  float radius2 = s.perception_radius * s.perception_radius;
  float cos_blind = cos(0.5 * s.blind_angle);
  bool sought_all_round = all_round(s);
  const int parts = int(kSearchParts);
  int cells = int(pc.search_cells);  // the list of the bird's part of its cell, for this cell
  ivec3 part = min(ivec3(inside * (float(parts) / cell)),
                   parts - 1);  // exact: cell / parts is a power of two
  int first = int(pc.search_first) + cells * (part.x + parts * (part.y + parts * part.z));
  float part2 = cell * cell / float(parts * parts);  // a part's side squared, exact
  float lattice = cell / float(kBoundSteps);         // grid_cells.comp's step, exact
  bool blocked = false, done = false;
  int n = 0;
  int e = 0, end = 0;  // its cell's birds yet to see, in slot order (ints: see nearer)
  vec3 low = vec3(0.0);
  // One loop over the cells and their birds, a lane taking its next bird each turn, and its next
  // cell in the same turn once its cell's birds are all seen: 8 lanes turn as often as the one
  // with the most birds and cells that hold none it looks at, not as often as the fullest of
  // their cells at each cell (roofline.md). A CPU device runs both halves of a turn for every
  // lane anyway: a turn for a cell alone would cost as much as one for a bird and a cell.
  // (The turns' bound, never reached, keeps a compiler from taking `done` as true after the loop.)
  for (int turn = 0; !done && turn < 0x40000000; ++turn) {
    // Its next bird, if its cell has one left. Out of any branch: a CPU device writes a variable
    // inside one under the lanes' mask, a blend more for each of the k kept.
    bool bird = e < end;
    vec4 point = imageLoad(grid_points, bird ? e : 0);
    uint j = floatBitsToUint(point.w);
    vec3 offset = low + point.xyz - inside;
    float d2 = dot(offset, offset);
    // Within sight, not itself, nearer than the k-th kept, not in the blind sector (flock.cpp:
    // sees).
    bool sees = bird && d2 <= radius2 && j != i && nearer(d2, j, worst_d2, worst) &&
                (sought_all_round || outside_blind(ahead, offset, d2, cos_blind));
    [[unroll]] for (uint m = 0u; m < kSeen; ++m) {
      bool takes = sees && m < k && nearer(d2, j, kept_d2[m], kept[m]);
      float was_d2 = kept_d2[m];
      uint was = kept[m];
      kept_d2[m] = takes ? d2 : was_d2;
      kept[m] = takes ? j : was;
      d2 = takes ? was_d2 : d2;
      j = takes ? was : j;
    }
    [[unroll]] for (uint m = 0u; m < kSeen; ++m) {
      if (m + 1u == k) {
        worst_d2 = kept_d2[m];
        worst = kept[m];
      }
    }
    e += bird ? 1 : 0;
    if (e < end) {  // birds of its cell still to see
    } else if (n >= cells || blocked) {
      done = true;
    } else {
      ivec4 around = imageLoad(grid_search, first + n);
      ++n;
      float least2 = float(around.w) * part2;  // exact
      if (least2 > radius2 || least2 > worst_d2) {
        done = true;  // nor can any cell after it hold a bird nearer
      } else {
        low = vec3(around.xyz) * cell;  // the cell's low corner
        float gap2 = gap2_to_box(low, low + cell, inside);
        if (!(gap2 > radius2 || gap2 > worst_d2)) {
          uvec4 range = cell_birds(home + around.xyz, b.flock, probing, blocked);
          // The box of its birds' places: a cell whose birds are all out of sight or farther than
          // the k-th kept is passed without looking at them (exact: the box's corners are whole
          // steps of a power of two, and a bird's offset rounds no nearer than the box's).
          gap2 = gap2_to_box(low + vec3(unpack_steps(range.z)) * lattice,
                             low + vec3(unpack_steps(range.w) + 1u) * lattice, inside);
          e = int(gap2 > radius2 || gap2 > worst_d2 ? range.y : range.x);
          end = int(range.y);
        }
      }
    }
  }
  if (!done) search_cut = true;
  near_count = 0u;
  [[unroll]] for (uint n = 0u; n < kSeen; ++n) {
    near_index[n] = kept[n];
    near_d2[n] = kept_d2[n];
    near_count += kept[n] != kNoBird ? 1u : 0u;
  }
  return blocked;
}

// flock.cpp: see_wakes. The places in the bird's tile; the step that read them at `step`.
void see_wakes(GpuSpecies s, GpuBird b, uint step, inout GpuPerception p) {
  vec3 ahead = flight_direction(b, step_wind);
  p.wake_step = step;
  p.wake_tile_x = b.tile_x;
  p.wake_tile_z = b.tile_z;
  for (uint e = 0u; e < near_count && p.wakes < kWakeSources; ++e) {
    GpuBird o = birds[near_index[e]];
    precise vec3 position = o.position + tile_shift(o.tile_x, o.tile_z, b.tile_x, b.tile_z);
    precise vec3 offset = position - b.position;
    if (dot(offset, ahead) <= 0.0 || length(offset) > kWakeReach * s.box_c) continue;
    vec3 air = o.velocity - wind_at(o.position.y);
    p.wake[p.wakes] = GpuWakeSource(vec4(position, o.phase), vec4(air, o.frequency), o.attitude,
                                    vec4(o.lift, o.amplitude, 0.0, 0.0));
    ++p.wakes;
  }
}

// flock.cpp: BeatPlaces, kept here for the bird whose formation() this is.
vec3 beat_at[kBeatSamples * 4u];

// flock.cpp: beat_places.
void beat_places(GpuSpecies s, GpuBird b, float shift) {
  for (uint k = 0u; k < kBeatSamples; ++k) {
    precise float beat = 2.0 * kPi * float(k) / float(kBeatSamples);
    vec3 right[2];
    right_wing_places(s, b.phase + shift + beat, b.amplitude, b.sweep, right);
    beat_at[4u * k] = right[0];
    beat_at[4u * k + 1u] = right[1];
    beat_at[4u * k + 2u] = right[0] * vec3(1.0, 1.0, -1.0);
    beat_at[4u * k + 3u] = right[1] * vec3(1.0, 1.0, -1.0);
  }
}

// flock.cpp: upwash_met_at, for up to kUpwashPlaces offsets, the wing places beat_at's.
const uint kUpwashPlaces = 5u;
void upwash_met_at(GpuSpecies s, GpuBird b, GpuPerception p, vec3 up, uint lead,
                   vec3 offsets[kUpwashPlaces], uint places, uint square_to,
                   out float met[kUpwashPlaces]) {
  for (uint o = 0u; o < kUpwashPlaces; ++o) met[o] = 0.0;
  if (!(b.frequency > 0.0)) return;
  for (uint k = 0u; k < kBeatSamples; ++k) {
    precise float beat = 2.0 * kPi * float(k) / float(kBeatSamples);
    uint at = 4u * ((k + lead) % kBeatSamples);
    // The wake square_to: one pair of vortices serves every place. (A block of its own: chosen
    // by an `if` inside the loop below, lavapipe was no faster.)
    if (p.wakes > 0u) {
      GpuWakeSource w = p.wake[square_to];
      precise float phase = w.position_phase.w + beat * w.air_velocity_frequency.w / b.frequency;
      w.position_phase.w = phase;
      for (uint q = 0u; q < 4u; ++q) {
        precise vec3 station = b.position + offsets[0] + rotate(b.attitude, beat_at[at + q]);
        VortexPair pair = vortex_pair(s, w, station);
        for (uint o = 0u; o < places; ++o) {
          precise float upwash = dot(pair_velocity(pair, station + (offsets[o] - offsets[0])), up);
          met[o] += upwash;
        }
      }
    }
    // The others: a pair for each place.
    for (uint m = 1u; m < p.wakes; ++m) {
      GpuWakeSource w = p.wake[m == square_to ? 0u : m];
      precise float phase = w.position_phase.w + beat * w.air_velocity_frequency.w / b.frequency;
      w.position_phase.w = phase;
      for (uint q = 0u; q < 4u; ++q) {
        precise vec3 station = b.position + offsets[0] + rotate(b.attitude, beat_at[at + q]);
        for (uint o = 0u; o < places; ++o) {
          precise vec3 at_offset = station + (offsets[o] - offsets[0]);
          precise float upwash = dot(wake_velocity(s, w, at_offset), up);
          met[o] += upwash;
        }
      }
    }
  }
  for (uint o = 0u; o < kUpwashPlaces; ++o) {
    precise float mean = met[o] / (4.0 * float(kBeatSamples));
    met[o] = mean;
  }
}

// flock.cpp: formation's met, at one offset.
float upwash_met(GpuSpecies s, GpuBird b, GpuPerception p, vec3 up, vec3 offset, uint lead) {
  vec3 offsets[kUpwashPlaces] =
      vec3[kUpwashPlaces](offset, vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  float met[kUpwashPlaces];
  upwash_met_at(s, b, p, up, lead, offsets, 1u, 0u, met);
  return met[0];
}

// flock.cpp: parabola_peak.
float parabola_peak(float below, float here, float above, float step, float most) {
  precise float slope = 0.5 * (above - below);
  precise float curvature = above - 2.0 * here + below;
  if (curvature < 0.0) return clamp(-slope / curvature * step, -most, most);
  return slope > 0.0 ? most : slope < 0.0 ? -most : 0.0;
}

// flock.cpp: Formation.
struct Formation {
  vec3 heading;
  float airspeed;
  float phase_rate;
  float fall_back;
};

// flock.cpp: formation.
Formation formation(GpuSpecies s, GpuBird b, vec3 wind, GpuPerception p) {
  Formation f = Formation(vec3(0.0), 0.0, 0.0, 0.0);
  if (s.w_formation <= 0.0) return f;
  int leader = -1, abreast = -1;
  for (uint m = 0u; m < p.wakes; ++m) {
    vec3 air = p.wake[m].air_velocity_frequency.xyz;
    float speed = length(air);
    if (!(speed > 0.0)) continue;
    precise float ahead_by = dot(p.wake[m].position_phase.xyz - b.position, air) / speed;
    if (ahead_by < kFormationBehind * s.box_c) {
      if (abreast < 0) abreast = int(m);
    } else if (leader < 0) {
      leader = int(m);
    }
  }
  if (leader < 0 && abreast < 0) return f;
  GpuWakeSource lead = p.wake[uint(leader >= 0 ? leader : abreast)];
  vec3 lead_air = lead.air_velocity_frequency.xyz;
  float speed = length(lead_air);
  vec3 ahead = lead_air / speed;
  vec3 side = cross(ahead, vec3(0.0, 1.0, 0.0));
  if (length(side) < 1e-6) return f;
  side = normalize(side);
  vec3 up = cross(side, ahead);
  float probe = kFormationProbe * s.box_c, most = kFormationReach * s.box_c;
  // flock.cpp: here and around, square to the flight ahead.
  vec3 places[kUpwashPlaces] =
      vec3[kUpwashPlaces](vec3(0.0), -probe * side, probe * side, -probe * up, probe * up);
  float around[kUpwashPlaces];
  beat_places(s, b, 0.0);  // a phase probe's are kPhaseProbeSamples moments on or back
  upwash_met_at(s, b, p, up, 0u, places, kUpwashPlaces, uint(leader >= 0 ? leader : abreast),
                around);
  float here = around[0];
  precise vec3 across_air = (b.velocity - wind) - lead_air;
  if (abreast >= 0) {
    float back = parabola_peak(upwash_met(s, b, p, up, probe * ahead, 0u), here,
                               upwash_met(s, b, p, up, -probe * ahead, 0u), probe, most);
    f.fall_back = max(back, 0.0) / s.formation_time;
  }
  if (leader < 0) return f;
  float across = parabola_peak(around[1], here, around[2], probe, most);
  float above = parabola_peak(around[3], here, around[4], probe, most);
  float shift = parabola_peak(upwash_met(s, b, p, up, vec3(0.0), kBeatSamples - kPhaseProbeSamples),
                              here, upwash_met(s, b, p, up, vec3(0.0), kPhaseProbeSamples),
                              kPhaseProbe, kPhaseReach);
  precise float closing_side = across / s.formation_time - dot(across_air, side);
  precise float closing_up = above / s.formation_time;  // by the offset alone (flock.cpp)
  f.heading = normalize(ahead + (side * closing_side + up * closing_up) / speed);
  precise vec3 offset = lead.position_phase.xyz - b.position;
  precise float behind = dot(offset, ahead);
  precise float across2 = max(dot(offset, offset) - behind * behind, 0.0);
  precise float keep = sqrt(max(s.separation_radius * s.separation_radius - across2, 0.0));
  precise float airspeed = s.cruise_speed + s.speed_gain * (behind - keep) - f.fall_back;
  f.airspeed = clamp(airspeed, s.min_speed, s.max_speed);
  f.phase_rate = shift / s.formation_time;
  return f;
}

// flock.cpp: route_direction.
vec3 route_direction(GpuSpecies s, vec3 to_goal) {
  vec3 way = horizontal(to_goal);
  float len = length(way);
  if (len <= s.height_capture) return unit_or_zero(to_goal);
  return unit_or_zero(way * (s.height_capture / len) + vec3(0.0, to_goal.y, 0.0));
}

// flock.cpp: route_heading.
vec3 route_heading(GpuSpecies s, vec3 to_goal, vec3 wind, float airspeed) {
  vec3 route = route_direction(s, to_goal);
  vec3 way = horizontal(route);
  vec3 aim = compensated_aim(way, track_aim(way, wind, airspeed), s.drift_compensation);
  vec3 level = length(aim) > 0.0 ? normalize(aim) * length(way) : way;
  return level + vec3(0.0, route.y, 0.0);
}

// flock.cpp: zone_distance.
float zone_distance(GpuSpecies s, vec3 offset, vec3 ahead) {
  float along = dot(offset, ahead);
  float across2 = max(dot(offset, offset) - along * along, 0.0);
  float front = along / s.separation_front;
  return sqrt(across2 + front * front);
}

// flock.cpp: nearest_offset.
vec3 nearest_offset(GpuSpecies s, vec3 offset, vec3 closing) {
  float closing2 = dot(closing, closing);
  if (!(s.separation_lookahead > 0.0) || !(closing2 > 0.0)) return offset;
  float t = clamp(-dot(offset, closing) / closing2, 0.0, s.separation_lookahead);
  vec3 nearest = offset + closing * t;
  return dot(nearest, offset) > 0.0 ? nearest : offset;
}

// flock.cpp: cohesion_pull.
float cohesion_pull(GpuSpecies s, vec3 cohesion, vec3 ahead) {
  float weights = s.w_route + s.w_alignment + s.w_cohesion;
  return weights > 0.0 ? s.cruise_speed * s.w_cohesion * dot(cohesion, ahead) / weights : 0.0;
}

// The social goal from the birds found (flock.cpp: social_goal).
GpuPerception social_goal(GpuSpecies s, GpuBird b, vec3 route_goal, bool route_done,
                          Formation formation) {
  GpuPerception p = no_perception();
  p.neighbours = near_count;
  if (near_count == 0u) return p;
  vec3 wind = step_wind;
  vec3 ahead = flight_direction(b, wind);
  vec3 separation = vec3(0.0), heading_sum = vec3(0.0), cohesion_sum = vec3(0.0);
  float ahead_sum = 0.0, close_sum = 0.0, faster_sum = 0.0;
  uint beyond = 0u, ahead_count = 0u, heeded = 0u;
  bool sought_all_round = all_round(s);
  float cos_blind = cos(0.5 * s.blind_angle);
  for (uint e = 0u; e < near_count; ++e) {
    vec4 place = imageLoad(grid_seen, int(2u * near_index[e]));
    vec4 motion = imageLoad(grid_seen, int(2u * near_index[e] + 1u));
    vec3 offset =
        place.xyz + tile_shift(int(place.w), int(motion.w), b.tile_x, b.tile_z) - b.position;
    float distance = length(offset);
    vec3 nearest = nearest_offset(s, offset, motion.xyz - b.velocity);
    float zone = zone_distance(s, nearest, ahead);
    if (zone < s.separation_radius)
      separation -= unit_or_zero(nearest) * square(1.0 - zone / s.separation_radius);
    if (sought_all_round && !outside_blind(ahead, offset, dot(offset, offset), cos_blind)) continue;
    ++heeded;
    if (distance >= s.separation_radius) cohesion_sum += offset;
    heading_sum += unit_or_zero(motion.xyz - wind);
    if (dot(offset, ahead) > 0.0) ++ahead_count;
    faster_sum += dot(motion.xyz - b.velocity, ahead);
    if (distance > 0.0) {
      float along = dot(offset, ahead) * (1.0 - s.separation_radius / distance);
      if (distance < s.separation_radius) {
        close_sum += along;
      } else {
        ahead_sum += along;
        ++beyond;
      }
    }
  }
  p.nearest = sqrt(near_d2[0]);
  for (uint e = 0u; e < near_count; ++e)
    p.seen_key += (ids[near_index[e]] & ~kGhostBird) * kSeenKeyFactor;
  vec3 route = route_done ? vec3(0.0)
                          : route_heading(s, route_goal - b.position, wind,
                                          length(horizontal(b.velocity - wind)));
  // The head of a formation flies its route (flock.cpp: social_goal).
  if (s.w_formation > 0.0 && !route_done && ahead_count == 0u) {
    p.airspeed = b.airspeed;
    p.direction = unit_or_zero(s.w_route * route + s.w_separation * separation);
    return p;
  }
  float along_total = close_sum + (beyond > 0u ? ahead_sum / float(beyond) : 0.0);
  float faster = heeded > 0u ? faster_sum / float(heeded) : 0.0;
  float pull = cohesion_pull(s, unit_or_zero(cohesion_sum), ahead);
  p.airspeed = clamp(s.cruise_speed + s.speed_gain * along_total + s.speed_match * faster + pull,
                     s.min_speed, s.max_speed);
  bool in_formation = formation.heading != vec3(0.0);
  p.airspeed =
      in_formation ? formation.airspeed : max(p.airspeed - formation.fall_back, s.min_speed);
  vec3 d = in_formation ? s.w_separation * separation +
                              s.w_formation * (formation.heading +
                                               kFormationRouteHeight * vec3(0.0, route.y, 0.0))
                        : s.w_route * route + s.w_separation * separation +
                              s.w_alignment * unit_or_zero(heading_sum) +
                              s.w_cohesion * unit_or_zero(cohesion_sum);
  p.direction = unit_or_zero(d);
  return p;
}
