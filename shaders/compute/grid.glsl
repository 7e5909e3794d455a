// The neighbour grid's cells (flock.cpp: grid_cell) and the slots of its table of the occupied
// cells, and when a bird perceives.
// A bird's cell, counted from the origin, and where it is inside it (each of x, y, z in
// [0, cell)), both exact: cells are 2^k cm and a whole number of them fill a tile (grid_shape).
ivec3 grid_cell(GpuBird b, float cell, out vec3 inside) {
  ivec3 c = ivec3(floor(b.position / cell));
  inside = b.position - vec3(c) * cell;
  int per_tile = int(kTile / cell);
  return c + ivec3(b.tile_x * per_tile, 0, b.tile_z * per_tile);
}

// Where the table's search for cell c of a flock starts: the cell's coordinates modulo the
// table's sides (pc.grid_bits: the host fits them to the flocks as they fly, gpu/grid_table.h),
// the flock's (an odd multiplier) mixed in by xor. Cells nearer than a side apart never start at
// one slot, so a flock within the sides finds its cells' slots at the first look; and cells side
// by side along x have slots side by side, so that neighbouring invocations (perceive.comp: one
// bird each, in slot order) search the same cells.
uint grid_slot(ivec3 c, uint flock) {
  uvec3 bits = uvec3(pc.grid_bits, pc.grid_bits >> 8u, pc.grid_bits >> 16u) & 31u;
  uvec3 u = uvec3(c) & ((uvec3(1u) << bits) - 1u);
  return (u.x | (u.y << bits.x) | (u.z << (bits.x + bits.y))) ^
         ((flock * 2654435761u) & (pc.buckets - 1u));
}

// A cell whose slot is taken tries the slot this far on, and so on (open addressing): an odd
// step, so that every slot is tried, from a hash of the cell (flock.cpp: grid_bucket's, and the
// flock's), so that the cells of a dense block of slots jump out of it rather than queue along it.
uint grid_probe_step(ivec3 c, uint flock, uint slots) {
  uint h = (uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u) ^
           (flock * 2654435761u);
  return ((h >> 11u) | 1u) & (slots - 1u);
}

// How often a bird perceives, in frames (flock.cpp: reaction_frames).
uint reaction_frames(GpuSpecies s, float frame_seconds) {
  return uint(max(1.0, floor(s.reaction_time / frame_seconds + 0.5)));
}
