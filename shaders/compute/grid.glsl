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
// table's sides, the flock's (an odd multiplier) mixed in by xor. The sides share the slots' bits,
// y's 4 to 8 times shorter than x's and z's (the built-in flocks are about 4 x 1 x 4 when spawned):
// with four slots a bird and cells of 2.56 m, 82 x 10 x 82 m for 1,000 birds, 164 x 41 x 164 m for
// 10,000, 328 x 82 x 328 m for 100,000, 655 x 164 x 655 m for 760,000. Cells nearer than a side
// apart never start at one slot, so a flock within the sides finds its cells' slots at the first
// look; and cells side by side along x have slots side by side, so that neighbouring invocations
// (perceive.comp: one bird each, in slot order) search the same cells.
uint grid_slot(ivec3 c, uint flock, uint slots) {
  uint bits = uint(findMSB(slots));
  uint by = (bits - 4u) / 3u, bx = (bits - by + 1u) / 2u, bz = bits - by - bx;
  uvec3 u = uvec3(c) & ((uvec3(1u) << uvec3(bx, by, bz)) - 1u);
  return (u.x | (u.y << bx) | (u.z << (bx + by))) ^ ((flock * 2654435761u) & (slots - 1u));
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
