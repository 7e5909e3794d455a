// The neighbour grid's cells and their hashed buckets (flock.cpp: grid_cell, grid_bucket).
ivec3 grid_cell(vec3 position, float cell) { return ivec3(floor(position / cell)); }

uint grid_bucket(ivec3 c, uint buckets) {
  uint h = (uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u);
  return h & (buckets - 1u);
}
