#version 450
// Each bird in the neighbour grid whose reaction is due sees its k nearest birds through it and
// sets its social goal (flock.glsl); the frame's steps then fly to it (step.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingPerception) buffer Perceptions {
  GpuPerception perception[];
};
layout(std430, set = 0, binding = kBindingIds) readonly buffer Ids { uint ids[]; };
// The grid as texels: a CPU device loads them for all its lanes at once, where it loads a storage
// buffer lane by lane, a branch each; and loads an image's inline, where it calls a function for a
// sampler's and saves every live register around it (gpu/compute.h: Binding).
layout(set = 0, binding = kBindingGridPoints, rgba32f) uniform readonly imageBuffer grid_points;
layout(set = 0, binding = kBindingGridKeys, rgba32i) uniform readonly iimageBuffer grid_keys;
layout(set = 0, binding = kBindingGridCells, rgba32ui) uniform readonly uimageBuffer grid_cells;
layout(set = 0, binding = kBindingGridSearch, rgba32i) uniform readonly iimageBuffer grid_search;
layout(set = 0, binding = kBindingGridSeen, rgba32f) uniform readonly imageBuffer grid_seen;
// model.glsl's kWakes: without wakes, their fields are neither found nor written.
#include "model.glsl"
// The most neighbours a species of the scenario sees (<= kMaxNeighbours): the search's registers;
// and whether every flocking species sees that many (then k is known here).
layout(constant_id = kModelConstants) const uint kSeen = kMaxNeighbours;
layout(constant_id = kModelConstants + 1) const bool kAllSeeKSeen = false;
#include "grid.glsl"
#include "flock.glsl"
// Counts the birds whose search a driver's limit on loops ended early (lavapipe ends a shader's
// loops after 65,535 turns: a cell of tens of thousands of birds); the host refuses the frame.
// And how far a sample of the searches reached (one bird in kReachSample, turn about): the host
// fits the grid's cell to them (flock.h: grid_cell_for); and how many of them searched again
// (GpuSimulation::searches).
layout(std430, set = 0, binding = kBindingCutShort) buffer CutShort {
  uint steps_short;  // step.glsl's
  uint searches_short;
  uint reached[kReachBins];
  uint searched_again;
};

// flock.cpp: perceive's reach, and reach_bin.
void count_reach(GpuSpecies s, uint k) {
  float reach2 = kFar;
  [[unroll]] for (uint m = 0u; m < kSeen; ++m) if (m + 1u == k) reach2 = near_d2[m];
  float reach = near_count < k ? s.perception_radius : sqrt(reach2);
  int bin = int(floor(2.0 * log2(max(reach, 1.0)))) - int(kReachFirstBin);
  atomicAdd(reached[clamp(bin, 0, int(kReachBins) - 1)], 1u);
}

void main() {
  // One bird of the grid each, in slot order: neighbouring invocations search the same cells.
  uint t = gl_GlobalInvocationID.x;
  if (t >= imageLoad(grid_cells, int(pc.buckets)).x) return;
  uint i = floatBitsToUint(imageLoad(grid_points, int(t)).w);
  if ((ids[i] & kGhostBird) != 0u) return;  // seen here, perceiving on its own rank
  GpuBird b = birds[i];
  GpuSpecies s = species[b.species];
  if (pc.frame % reaction_frames(s, pc.frame_seconds) != 0u) return;
  near_count = 0u;
  // The air it flies in: its search looks along its flight through it.
  step_wind = wind_at(b.position.y);
  uint k = kAllSeeKSeen ? kSeen : uint(s.neighbours);
  search_cut = false;
  bool again = k >= 1u && search(i, b, s, k, false);
  if (again) search(i, b, s, k, true);
  if (search_cut) atomicAdd(searches_short, 1u);
  if (k >= 1u && (i + pc.frame) % kReachSample == 0u) {
    count_reach(s, k);
    if (again) atomicAdd(searched_again, 1u);
  }
  vec3 goal = vec3(0.0);
  bool route_done = false;
  if (near_count > 0u) {  // route_goal passes targets: the step does that, not the eyes
    GpuBird route_bird = b;
    Leg leg = load_leg(route_bird, pc.targets_base);
    goal = route_goal(route_bird, s, leg);
    route_done = route_over(route_bird, leg);
    vec3 on;
    if (onward_goal(route_bird, leg, on)) {
      goal = on;
      route_done = false;
    }
  }
  GpuPerception wakes = no_perception();
  Formation f = Formation(vec3(0.0), 0.0, 0.0, 0.0);
  if (kWakes && (b.flocking & kFeelsWakes) != 0u) {
    see_wakes(s, b, pc.step.x, wakes);
    f = formation(s, b, step_wind, wakes);
  }
  GpuPerception p = social_goal(s, b, goal, route_done, f);
  if (kWakes) {
    p.wakes = wakes.wakes;
    p.wake_step = wakes.wake_step;
    p.wake_tile_x = wakes.wake_tile_x;
    p.wake_tile_z = wakes.wake_tile_z;
    p.wake = wakes.wake;
    p.phase_rate = f.phase_rate;
    perception[i] = p;
  } else {
    perception[i].direction = p.direction;
    perception[i].airspeed = p.airspeed;
    perception[i].neighbours = p.neighbours;
    perception[i].nearest = p.nearest;
    perception[i].seen_key = p.seen_key;
  }
}
