#version 450
// The neighbour grid, 4 of 4: each bird in the grid writes its index, cell, place in the cell and
// flock at its bucket's start plus its rank: the birds in bucket order, compact for the search.
#extension GL_GOOGLE_include_directive : require
#define BIRDS_ACCESS readonly
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) readonly buffer GridPlace { uvec2 grid_place[]; };
layout(std430, set = 0, binding = kBindingGridStarts) readonly buffer GridStarts { uint grid_starts[]; };
layout(std430, set = 0, binding = kBindingGridBlocks) readonly buffer GridBlocks { uint grid_blocks[]; };
layout(std430, set = 0, binding = kBindingGridSorted) writeonly buffer GridSorted { uint grid_sorted[]; };
layout(std430, set = 0, binding = kBindingGridPoints) writeonly buffer GridPoints { vec4 grid_points[]; };
layout(std430, set = 0, binding = kBindingGridCells) writeonly buffer GridCells { ivec4 grid_cells[]; };
#include "bird.glsl"
#include "grid.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  uvec2 place = grid_place[i];
  if (place.x == kNoBucket) return;
  uint slot = grid_starts[place.x] + grid_blocks[place.x / kScanBlock] + place.y;
  grid_sorted[slot] = i;
  GpuBird b = birds[i];
  vec3 inside;
  grid_cells[slot] = ivec4(grid_cell(b, pc.grid_cell, inside), 0);
  grid_points[slot] = vec4(inside, uintBitsToFloat(b.flock));  // what the search reads
}
