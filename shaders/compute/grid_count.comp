#version 450
// The neighbour grid, 1 of 4 (a counting sort): each bird that flocks now counts itself into its
// cell's bucket; its rank there is the count before it. A bird that does not, and whose reaction
// is due, sees no one (perceive.comp perceives for the birds in the grid).
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) writeonly buffer GridPlace { uvec2 grid_place[]; };
layout(std430, set = 0, binding = kBindingGridCounts) buffer GridCounts { uint grid_counts[]; };
layout(std430, set = 0, binding = kBindingPerception) writeonly buffer Perceptions { GpuPerception perception[]; };
#include "model.glsl"
#include "grid.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  GpuBird b = birds[i];
  uvec2 place = uvec2(kNoBucket, 0u);
  if (flocks_now(b)) {
    vec3 inside;
    place.x = grid_bucket(grid_cell(b, pc.grid_cell, inside), pc.buckets);
    place.y = atomicAdd(grid_counts[place.x], 1u);
  } else if (pc.frame % reaction_frames(species[b.species], pc.frame_seconds) == 0u) {
    perception[i] = GpuPerception(vec3(0.0), 0.0, 0u, 0.0, 0u, 0u);
  }
  grid_place[i] = place;
}
