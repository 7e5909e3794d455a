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
// table's sides (x, z, y share its bits, x first), the flock's (an odd multiplier) mixed in by
// xor. Cells nearer than a side apart never start at one slot, so a compact flock's cells find
// theirs at the first look; and cells side by side along x have slots side by side, so that
// neighbouring invocations (perceive.comp: one bird each, in slot order) search the same cells.
// A cell whose slot is taken takes the next free one (linear probing, grid_count.comp).
uint grid_slot(ivec3 c, uint flock, uint slots) {
  uint bits = uint(findMSB(slots));
  uint bx = (bits + 2u) / 3u, bz = (bits + 1u) / 3u, by = bits / 3u;
  uvec3 u = uvec3(c) & ((uvec3(1u) << uvec3(bx, by, bz)) - 1u);
  return (u.x | (u.y << bx) | (u.z << (bx + by))) ^ ((flock * 2654435761u) & (slots - 1u));
}

// How often a bird perceives, in frames (flock.cpp: reaction_frames).
uint reaction_frames(GpuSpecies s, float frame_seconds) {
  return uint(max(1.0, floor(s.reaction_time / frame_seconds + 0.5)));
}
