#version 450
// The neighbour grid, 4 of 5: each bird in the grid writes its place in its cell and its index at
// its slot's first (grid_scan.glsl) plus its rank: the birds in slot order, compact for the search;
// and what the social goal reads of it.
#extension GL_GOOGLE_include_directive : require
#define BIRDS_ACCESS readonly
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) readonly buffer GridPlace {
  uvec2 grid_place[];
};
layout(std430, set = 0, binding = kBindingGridStarts) readonly buffer GridStarts {
  uint grid_starts[];
};
layout(std430, set = 0, binding = kBindingGridBlocks) readonly buffer GridBlocks {
  uint grid_blocks[];
};
layout(std430, set = 0, binding = kBindingGridPoints) writeonly buffer GridPoints {
  vec4 grid_points[];
};
layout(std430, set = 0, binding = kBindingGridSeen) writeonly buffer GridSeen { vec4 grid_seen[]; };
#include "bird.glsl"
#include "grid.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  uvec2 place = grid_place[i];
  if (place.x == kNoBucket) return;
  uint e = grid_starts[place.x] + grid_blocks[place.x / kScanBlock] + place.y;
  vec3 inside;
  grid_cell(birds[i], pc.grid_cell, inside);
  grid_points[e] = vec4(inside, uintBitsToFloat(i));
  GpuBird b = birds[i];
  grid_seen[2u * i] = vec4(b.position, float(b.tile_x));
  grid_seen[2u * i + 1u] = vec4(b.velocity, float(b.tile_z));
}
