// The neighbour grid's cells and their hashed buckets (flock.cpp: grid_cell, grid_bucket), and
// when a bird perceives.
// A bird's cell, counted from the origin, and where it is inside it (each of x, y, z in
// [0, cell)), both exact: cells are 2^k cm and a whole number of them fill a tile (grid_shape).
ivec3 grid_cell(GpuBird b, float cell, out vec3 inside) {
  ivec3 c = ivec3(floor(b.position / cell));
  inside = b.position - vec3(c) * cell;
  int per_tile = int(kTile / cell);
  return c + ivec3(b.tile_x * per_tile, 0, b.tile_z * per_tile);
}

uint grid_bucket(ivec3 c, uint buckets) {
  uint h = (uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u);
  return h & (buckets - 1u);
}

// How often a bird perceives, in frames (flock.cpp: reaction_frames).
uint reaction_frames(GpuSpecies s, float frame_seconds) {
  return uint(max(1.0, floor(s.reaction_time / frame_seconds + 0.5)));
}
