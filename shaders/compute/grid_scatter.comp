#version 450
// The neighbour grid, 4 of 4: each bird in the grid writes its index at its bucket's start plus
// its rank: the birds in bucket order.
#extension GL_GOOGLE_include_directive : require
#include "gpu/host_device.h"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) readonly buffer GridPlace { uvec2 grid_place[]; };
layout(std430, set = 0, binding = kBindingGridStarts) readonly buffer GridStarts { uint grid_starts[]; };
layout(std430, set = 0, binding = kBindingGridBlocks) readonly buffer GridBlocks { uint grid_blocks[]; };
layout(std430, set = 0, binding = kBindingGridSorted) writeonly buffer GridSorted { uint grid_sorted[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  uvec2 place = grid_place[i];
  if (place.x == kNoBucket) return;
  grid_sorted[grid_starts[place.x] + grid_blocks[place.x / kScanBlock] + place.y] = i;
}
