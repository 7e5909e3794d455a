#version 450
// The neighbour grid, 5 of 5: each occupied slot's range in the sorted birds, first and end, from
// the prefix sum's two levels (grid_scan.glsl) and its count, and the bounds of its birds' places
// in their cell, for the search (flock.glsl: search passes a cell whose birds are all farther
// than its k-th kept); written by its first bird, one invocation a bird in slot order. The bounds
// are on a lattice of kBoundSteps to the cell's side, rounded outwards: exact, as cells are 2^k
// cm (grid.glsl). The slot after the last holds the birds in the grid (x).
#extension GL_GOOGLE_include_directive : require
#include "gpu/host_device.h"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridCounts) readonly buffer GridCounts {
  uint grid_counts[];
};
layout(std430, set = 0, binding = kBindingGridStarts) readonly buffer GridStarts {
  uint grid_starts[];
};
layout(std430, set = 0, binding = kBindingGridBlocks) readonly buffer GridBlocks {
  uint grid_blocks[];
};
layout(std430, set = 0, binding = kBindingGridPlace) readonly buffer GridPlace {
  uvec2 grid_place[];
};
layout(std430, set = 0, binding = kBindingGridPoints) readonly buffer GridPoints {
  vec4 grid_points[];
};
layout(std430, set = 0, binding = kBindingGridCells) writeonly buffer GridCells {
  uvec4 grid_cells[];
};

// A place's lattice steps along each axis, 10 bits each in one word.
uint pack_steps(uvec3 q) { return q.x | (q.y << 10u) | (q.z << 20u); }

// Where slot k's birds start in slot order.
uint slot_first(uint k) { return grid_starts[k] + grid_blocks[k / kScanBlock]; }

void main() {
  uint t = gl_GlobalInvocationID.x;
  uint last = pc.buckets - 1u, birds = slot_first(last) + grid_counts[last];
  if (t == 0u) grid_cells[pc.buckets] = uvec4(birds, 0u, 0u, 0u);
  if (t >= birds) return;
  uint k = grid_place[floatBitsToUint(grid_points[t].w)].x;
  uint first = slot_first(k);
  if (t != first) return;
  uint end = first + grid_counts[k];
  float per_step = float(kBoundSteps) / pc.grid_cell;  // a power of two: exact
  uvec3 low = uvec3(kBoundSteps - 1u), high = uvec3(0u);
  uint e = first;
  for (; e < end; ++e) {
    uvec3 q = min(uvec3(grid_points[e].xyz * per_step), uvec3(kBoundSteps - 1u));
    low = min(low, q);
    high = max(high, q);
  }
  if (e < end) {  // a driver's limit on loops ended it: the whole cell, which holds them all
    low = uvec3(0u);
    high = uvec3(kBoundSteps - 1u);
  }
  grid_cells[k] = uvec4(first, end, pack_steps(low), pack_steps(high));
}
