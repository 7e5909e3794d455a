// Flocking (engine/model/flock.cpp, the same in float): the neighbour grid's cells and buckets,
// what a bird sees, its k nearest by a search of the grid ring by ring, and its social goal.
// The includer declares the grid's buffers and includes model.glsl first (perceive.comp).

#include "grid.glsl"

vec3 unit_or_zero(vec3 v) {
  float l = length(v);
  return l > 0.0 ? v / l : vec3(0.0);
}

vec3 flight_direction(GpuBird b) {
  return length(b.velocity) > 0.0 ? normalize(b.velocity) : rotate(b.attitude, vec3(1, 0, 0));
}

// Outside the blind sector (flock.cpp: sees, less the radius): `cos_blind` = cos(blind_angle / 2).
bool outside_blind(vec3 ahead, vec3 offset, float distance2, float cos_blind) {
  return -dot(offset, ahead) <= cos_blind * sqrt(distance2);
}

// The k nearest so far, nearest first, ties by index.
uint near_index[kMaxNeighbours];
float near_d2[kMaxNeighbours];
uint near_count;

bool near_full(uint k) { return near_count >= k; }

bool beats_worst(uint k, uint j, float d2) {
  return !near_full(k) || d2 < near_d2[k - 1u] || (d2 == near_d2[k - 1u] && j < near_index[k - 1u]);
}

// Inserts bird j (it beats the worst: beats_worst).
void offer(uint k, uint j, float d2) {
  uint at = min(near_count, k - 1u);  // the last slot is overwritten when full
  while (at > 0u && (near_d2[at - 1u] > d2 || (near_d2[at - 1u] == d2 && near_index[at - 1u] > j))) {
    near_index[at] = near_index[at - 1u];
    near_d2[at] = near_d2[at - 1u];
    --at;
  }
  near_index[at] = j;
  near_d2[at] = d2;
  near_count = min(near_count + 1u, k);
}

uint bucket_start(uint k) { return grid_starts[k] + grid_blocks[k / kScanBlock]; }

// Bird i's k nearest seen birds of its flock (flock.cpp: NeighbourGrid::seen_by), in the frame of
// its cell's low corner: cells and places in them are exact (grid.glsl), so the offsets between
// birds are as fine 1,000 km out as at the origin.
void search(uint i, GpuBird b, GpuSpecies s, uint k) {
  near_count = 0u;
  vec3 ahead = flight_direction(b);
  float cell = pc.grid_cell;
  vec3 inside;
  ivec3 home = grid_cell(b, cell, inside);
  int rings = int(ceil(s.perception_radius / cell));
  float radius2 = s.perception_radius * s.perception_radius;
  float cos_blind = cos(0.5 * s.blind_angle);
  vec3 to_edge = min(inside, cell - inside);
  float edge = max(0.0, min(to_edge.x, min(to_edge.y, to_edge.z)));
  for (int r = 0; r <= rings; ++r) {
    float inner = float(r - 1) * cell + edge;
    if (r > 0 && near_full(k) && inner * inner >= near_d2[k - 1u]) break;
    for (int dx = -r; dx <= r; ++dx)
      for (int dy = -r; dy <= r; ++dy) {
        bool side = abs(dx) == r || abs(dy) == r;
        for (int dz = -r; dz <= r; dz += side ? 1 : max(2 * r, 1)) {
          ivec3 dc = ivec3(dx, dy, dz);
          vec3 low = vec3(dc) * cell;  // the cell's low corner
          vec3 gap = max(max(low - inside, inside - (low + cell)), vec3(0.0));
          float gap2 = dot(gap, gap);
          if (gap2 > radius2 || (near_full(k) && gap2 > near_d2[k - 1u])) continue;
          ivec3 c = home + dc;
          uint bucket = grid_bucket(c, pc.buckets);
          uint first = bucket_start(bucket);
          uint end = first + grid_counts[bucket];
          for (uint e = first; e < end; ++e) {
            vec4 point = grid_points[e];  // only birds that flock now are in the grid
            vec3 offset = low + point.xyz - inside;  // if it is in cell c (checked below)
            float d2 = dot(offset, offset);
            if (d2 > radius2 || floatBitsToUint(point.w) != b.flock || (near_full(k) && d2 > near_d2[k - 1u])) continue;
            uint j = grid_sorted[e];
            // Not itself, nearer than the worst so far, in this very cell (not one hashed into the
            // same bucket: each bird is met once), and not in the blind sector.
            if (j == i || !beats_worst(k, j, d2) || grid_cells[e].xyz != c || !outside_blind(ahead, offset, d2, cos_blind))
              continue;
            offer(k, j, d2);
          }
        }
      }
  }
}

// The social goal from the birds found (flock.cpp: social_goal).
GpuPerception social_goal(GpuSpecies s, GpuBird b, vec3 route_goal) {
  GpuPerception p = GpuPerception(vec3(0.0), 0.0, near_count, 0.0, 0u, 0u);
  if (near_count == 0u) return p;
  vec3 ahead = flight_direction(b);
  vec3 separation = vec3(0.0), heading_sum = vec3(0.0), cohesion_sum = vec3(0.0);
  float ahead_sum = 0.0, close_sum = 0.0, faster_sum = 0.0;
  uint beyond = 0u;
  for (uint e = 0u; e < near_count; ++e) {
    GpuBird o = birds[near_index[e]];
    vec3 offset = o.position + tile_shift(o.tile_x, o.tile_z, b.tile_x, b.tile_z) - b.position;
    float distance = length(offset);
    if (distance < s.separation_radius)
      separation -= unit_or_zero(offset) * pow(1.0 - distance / s.separation_radius, 2.0);
    else
      cohesion_sum += offset;
    heading_sum += unit_or_zero(o.velocity);
    faster_sum += dot(o.velocity - b.velocity, ahead);
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
  for (uint e = 0u; e < near_count; ++e) p.seen_key += near_index[e] * kSeenKeyFactor;
  vec3 d = s.w_route * unit_or_zero(route_goal - b.position) + s.w_separation * separation +
           s.w_alignment * unit_or_zero(heading_sum) + s.w_cohesion * unit_or_zero(cohesion_sum);
  p.direction = unit_or_zero(d);
  float along_total = close_sum + (beyond > 0u ? ahead_sum / float(beyond) : 0.0);
  float faster = faster_sum / float(near_count);
  p.airspeed = clamp(s.cruise_speed + s.speed_gain * along_total + s.speed_match * faster, s.min_speed, s.max_speed);
  return p;
}
