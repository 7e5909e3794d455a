// The neighbour grid's cells and their hashed buckets (flock.cpp: grid_cell, grid_bucket), and
// when a bird perceives.
ivec3 grid_cell(vec3 position, float cell) { return ivec3(floor(position / cell)); }

uint grid_bucket(ivec3 c, uint buckets) {
  uint h = (uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u);
  return h & (buckets - 1u);
}

// How often a bird perceives, in frames (flock.cpp: reaction_frames).
uint reaction_frames(GpuSpecies s, float frame_seconds) {
  return uint(max(1.0, floor(s.reaction_time / frame_seconds + 0.5)));
}
