// The neighbour grid, 2 and 3 of 5: the exclusive prefix sum of the slots' counts in two
// levels. grid_scan_blocks.comp: each workgroup scans kScanBlock slots into grid_starts (within
// its block) and writes the block's total; grid_scan_totals.comp (one workgroup) scans the totals
// in place. A slot k starts at grid_starts[k] + grid_blocks[k / kScanBlock] (grid_scatter.comp,
// grid_cells.comp).
#include "gpu/host_device.h"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridCounts) readonly buffer GridCounts {
  uint grid_counts[];
};
layout(std430, set = 0, binding = kBindingGridStarts) buffer GridStarts { uint grid_starts[]; };
layout(std430, set = 0, binding = kBindingGridBlocks) buffer GridBlocks { uint grid_blocks[]; };

shared uint partial[kWorkgroupSize];

// The exclusive prefix sum of `value` over the workgroup's invocations (Hillis-Steele).
uint workgroup_exclusive(uint value, out uint total) {
  uint t = gl_LocalInvocationID.x;
  partial[t] = value;
  barrier();
  for (uint step = 1u; step < kWorkgroupSize; step <<= 1u) {
    uint add = t >= step ? partial[t - step] : 0u;
    barrier();
    partial[t] += add;
    barrier();
  }
  total = partial[kWorkgroupSize - 1u];
  return partial[t] - value;
}

#ifdef SCAN_TOTALS
void main() {
  uint blocks = pc.buckets / kScanBlock;
  uint per = (blocks + kWorkgroupSize - 1u) / kWorkgroupSize;
  uint first = min(gl_LocalInvocationID.x * per, blocks), end = min(first + per, blocks);
  uint sum = 0u;
  for (uint e = first; e < end; ++e) sum += grid_blocks[e];
  uint total;
  uint running = workgroup_exclusive(sum, total);
  for (uint e = first; e < end; ++e) {
    uint v = grid_blocks[e];
    grid_blocks[e] = running;
    running += v;
  }
}
#else
const uint kPerInvocation = kScanBlock / kWorkgroupSize;

void main() {
  uint first = gl_WorkGroupID.x * kScanBlock + gl_LocalInvocationID.x * kPerInvocation;
  uint sum = 0u;
  for (uint e = 0u; e < kPerInvocation; ++e) sum += grid_counts[first + e];
  uint total;
  uint running = workgroup_exclusive(sum, total);
  for (uint e = 0u; e < kPerInvocation; ++e) {
    grid_starts[first + e] = running;
    running += grid_counts[first + e];
  }
  if (gl_LocalInvocationID.x == 0u) grid_blocks[gl_WorkGroupID.x] = total;
}
#endif
