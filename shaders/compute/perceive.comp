#version 450
// Each bird in the neighbour grid whose reaction is due sees its k nearest birds through it and
// sets its social goal (flock.glsl); the frame's steps then fly to it (step.glsl).
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingPerception) buffer Perceptions { GpuPerception perception[]; };
layout(std430, set = 0, binding = kBindingGridCounts) readonly buffer GridCounts { uint grid_counts[]; };
layout(std430, set = 0, binding = kBindingGridStarts) readonly buffer GridStarts { uint grid_starts[]; };
layout(std430, set = 0, binding = kBindingGridBlocks) readonly buffer GridBlocks { uint grid_blocks[]; };
layout(std430, set = 0, binding = kBindingGridSorted) readonly buffer GridSorted { uint grid_sorted[]; };
layout(std430, set = 0, binding = kBindingGridPoints) readonly buffer GridPoints { vec4 grid_points[]; };
layout(std430, set = 0, binding = kBindingGridCells) readonly buffer GridCells { ivec4 grid_cells[]; };
#include "model.glsl"
#include "flock.glsl"

void main() {
  // One bird of the grid each, in bucket order: neighbouring invocations search the same cells.
  uint t = gl_GlobalInvocationID.x;
  uint last = pc.buckets - 1u;
  if (t >= bucket_start(last) + grid_counts[last]) return;
  uint i = grid_sorted[t];
  GpuBird b = birds[i];
  GpuSpecies s = species[b.species];
  if (pc.frame % reaction_frames(s, pc.frame_seconds) != 0u) return;
  near_count = 0u;
  if (s.neighbours >= 1.0) search(i, b, s, uint(s.neighbours));
  vec3 goal = vec3(0.0);
  if (near_count > 0u) {  // route_goal passes targets: the step does that, not the eyes
    GpuBird route_bird = b;
    Leg leg = load_leg(route_bird, 0u);
    step_wind = wind_at(b.position.y);
    goal = route_goal(route_bird, s, leg);
  }
  perception[i] = social_goal(s, b, goal);
}
