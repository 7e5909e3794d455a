#version 450
// The neighbour grid, 1 of 5: each bird that flocks now finds its cell's slot in the table,
// claiming an empty one if its cell has none yet (the table has more slots than birds and its
// probing step is odd: a search always ends), and counts itself into it; its rank there is the
// count before it. A bird that does not, and whose reaction is due, sees no one (perceive.comp
// perceives for the birds in the grid).
#extension GL_GOOGLE_include_directive : require
#include "buffers.glsl"
layout(local_size_x = kWorkgroupSize) in;
layout(push_constant) uniform StepPush { StepConstants pc; };
layout(std430, set = 0, binding = kBindingGridPlace) writeonly buffer GridPlace {
  uvec2 grid_place[];
};
layout(std430, set = 0, binding = kBindingGridCounts) buffer GridCounts { uint grid_counts[]; };
layout(std430, set = 0, binding = kBindingGridKeys) writeonly buffer GridKeys {
  ivec4 grid_keys[];
};
layout(std430, set = 0, binding = kBindingGridOwners) buffer GridOwners { uint grid_owners[]; };
layout(std430, set = 0, binding = kBindingPerception) writeonly buffer Perceptions {
  GpuPerception perception[];
};
#include "model.glsl"
#include "grid.glsl"

// The slot of cell c of bird i's flock. A slot is claimed by one bird, which writes its key for
// the search; the others tell their cell's slot by the claimer's own cell (its key may not be
// written yet), so two cells never share a slot.
uint claim_slot(uint i, ivec3 c, uint flock) {
  uint slot = grid_slot(c, flock), step = grid_probe_step(c, flock, pc.buckets);
  for (uint probe = 0u; probe < pc.buckets; ++probe) {
    uint owner = atomicCompSwap(grid_owners[slot], kNoBird, i);
    if (owner == kNoBird) {
      grid_keys[slot] = ivec4(c, int(flock));
      return slot;
    }
    vec3 unused;
    if (birds[owner].flock == flock && grid_cell(birds[owner], pc.grid_cell, unused) == c)
      return slot;
    slot = (slot + step) & (pc.buckets - 1u);
  }
  return kNoBucket;  // never: the table cannot fill
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.bird_count) return;
  GpuBird b = birds[i];
  uvec2 place = uvec2(kNoBucket, 0u);
  if (flocks_now(b)) {
    vec3 inside;
    place.x = claim_slot(i, grid_cell(b, pc.grid_cell, inside), b.flock);
    if (place.x != kNoBucket) place.y = atomicAdd(grid_counts[place.x], 1u);
  } else if (pc.frame % reaction_frames(species[b.species], pc.frame_seconds) == 0u) {
    perception[i] = no_perception();
  }
  grid_place[i] = place;
}
