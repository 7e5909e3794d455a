// The neighbour grid, 2 and 3 of 5: the exclusive prefix sum of the slots' counts in two
// levels. grid_scan_blocks.comp: each workgroup scans kScanBlock slots into grid_starts (within
// its block) and writes the block's total; grid_scan_totals.comp (one workgroup) scans the totals
// in place. A slot k starts at grid_starts[k] + grid_blocks[k / kScanBlock] (grid_scatter.comp,
// grid_cells.comp).
#include "gpu/host_device.h"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridBlocks) buffer GridBlocks { uint grid_blocks[]; };

// The workgroup's invocations in runs of kRun.
const uint kRun = 8u, kRuns = kWorkgroupSize / kRun;
shared uint partial[kWorkgroupSize];
shared uint run_totals[kRuns];

// The exclusive prefix sum of `value` over the workgroup's invocations: each run's within it, by
// one invocation, then the runs' totals before it. Two barriers (a CPU device runs each as a
// switch of every invocation), where a scan of log2(kWorkgroupSize) steps takes 2 a step.
uint workgroup_exclusive(uint value, out uint total) {
  uint t = gl_LocalInvocationID.x;
  partial[t] = value;
  barrier();
  if (t < kRuns) {
    uint sum = 0u;
    for (uint e = t * kRun; e < (t + 1u) * kRun; ++e) {
      uint v = partial[e];
      partial[e] = sum;
      sum += v;
    }
    run_totals[t] = sum;
  }
  barrier();
  uint before = 0u;
  total = 0u;
  for (uint r = 0u; r < kRuns; ++r) {
    before += r < t / kRun ? run_totals[r] : 0u;
    total += run_totals[r];
  }
  return partial[t] + before;
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
// Each invocation's slots, read and written four to a vector: a CPU device (lavapipe) reaches a
// storage buffer lane by lane, so a uvec4 costs as much as a uint.
layout(std430, set = 0, binding = kBindingGridCounts) readonly buffer GridCounts {
  uvec4 grid_counts4[];
};
layout(std430, set = 0, binding = kBindingGridStarts) writeonly buffer GridStarts {
  uvec4 grid_starts4[];
};
const uint kVectors = kScanBlock / kWorkgroupSize / 4u;

void main() {
  uint first = (gl_WorkGroupID.x * kScanBlock + gl_LocalInvocationID.x * 4u * kVectors) / 4u;
  uvec4 counts[kVectors];
  uint sum = 0u;
  for (uint e = 0u; e < kVectors; ++e) {
    counts[e] = grid_counts4[first + e];
    sum += counts[e].x + counts[e].y + counts[e].z + counts[e].w;
  }
  uint total;
  uint running = workgroup_exclusive(sum, total);
  for (uint e = 0u; e < kVectors; ++e) {
    uvec4 c = counts[e];
    grid_starts4[first + e] = running + uvec4(0u, c.x, c.x + c.y, c.x + c.y + c.z);
    running += c.x + c.y + c.z + c.w;
  }
  if (gl_LocalInvocationID.x == 0u) grid_blocks[gl_WorkGroupID.x] = total;
}
#endif
