#version 450
// The neighbour grid, 1 of 4 (a counting sort): each bird that flocks now counts itself into its
// cell's bucket; its rank there is the count before it.
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) writeonly buffer GridPlace { uvec2 grid_place[]; };
layout(std430, set = 0, binding = kBindingGridCounts) buffer GridCounts { uint grid_counts[]; };
#include "model.glsl"
#include "grid.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  GpuBird b = birds[i];
  uvec2 place = uvec2(kNoBucket, 0u);
  if (flocks_now(b)) {
    place.x = grid_bucket(grid_cell(b.position, pc.grid_cell), pc.buckets);
    place.y = atomicAdd(grid_counts[place.x], 1u);
  }
  grid_place[i] = place;
}
