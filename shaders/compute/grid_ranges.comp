#version 450
// The neighbour grid, 4 of 5: each slot's range in the sorted birds, first and end, from the
// prefix sum's two levels (grid_scan.glsl) and its count.
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
layout(std430, set = 0, binding = kBindingGridRanges) writeonly buffer GridRanges {
  uvec2 grid_ranges[];
};

void main() {
  // As many slots an invocation as it takes (a device dispatches at most 65,535 workgroups a row).
  for (uint k = gl_GlobalInvocationID.x; k < pc.buckets; k += gl_NumWorkGroups.x * kWorkgroupSize) {
    uint first = grid_starts[k] + grid_blocks[k / kScanBlock];
    grid_ranges[k] = uvec2(first, first + grid_counts[k]);
  }
}
