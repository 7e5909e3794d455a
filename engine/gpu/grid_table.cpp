#include "gpu/grid_table.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "gpu/layout.h"
#include "model/flock.h"

namespace aeroflock::gpu {
namespace {

// The bits of the least power of two >= n (n >= 1).
uint32_t bits_for(uint64_t n) { return uint32_t(std::bit_width(std::max<uint64_t>(n, 1) - 1)); }

// The p-th quantile (0 to 1) of `v`, which it reorders: below the middle the element at or
// below it, above the middle at or above it (a flock of a few birds spans them all).
int quantile_of(std::vector<int>& v, double p) {
  const double at_rank = p * double(v.size() - 1);
  const auto at = v.begin() + std::ptrdiff_t(p < 0.5 ? std::floor(at_rank) : std::ceil(at_rank));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

}  // namespace

GridTable grid_table(uint32_t bits) {
  const uint32_t y = bits >= 4 ? (bits - 4) / 3 : 0;
  const uint32_t x = (bits - y + 1) / 2;
  return {x, y, bits - y - x};
}

std::vector<glm::ivec3> flock_extents(std::span<const GpuBird> birds, double cell, uint32_t flocks,
                                      uint32_t samples) {
  auto in_grid = [flocks](const GpuBird& b) {  // flocks_now, of a flock there is
    return b.flocking != 0 && b.mode == uint32_t(FlightMode::flying) &&
           b.landing_stage == uint32_t(LandingStage::none) && b.flock < flocks;
  };
  // Each flock's birds in the grid, then every stride-th of them: a million birds are read
  // twice, their cells computed for a few thousand.
  std::vector<size_t> members(flocks, 0), seen(flocks, 0);
  for (const GpuBird& b : birds)
    if (in_grid(b)) ++members[b.flock];
  std::vector<std::array<std::vector<int>, 3>> cells(flocks);
  for (const GpuBird& b : birds) {
    if (!in_grid(b)) continue;
    const size_t stride = std::max<size_t>(1, members[b.flock] / std::max(samples, 1u));
    if (seen[b.flock]++ % stride != 0) continue;
    // The device's cell (grid.glsl), exact in double: a whole number of cells fills a tile.
    const glm::ivec3 c = grid_cell(glm::dvec3(b.position) + tile_centre(b.tile_x, b.tile_z), cell);
    for (int a = 0; a < 3; ++a) cells[b.flock][a].push_back(c[a]);
  }
  std::vector<glm::ivec3> extents;
  for (std::array<std::vector<int>, 3>& axis : cells) {
    if (axis[0].empty()) continue;
    glm::ivec3 extent;
    for (int a = 0; a < 3; ++a)
      extent[a] = quantile_of(axis[a], 0.99) - quantile_of(axis[a], 0.01) + 1;
    extents.push_back(extent);
  }
  return extents;
}

GridTable grid_table_for(std::span<const glm::ivec3> extents, int margin, uint32_t least,
                         uint32_t most) {
  if (extents.empty()) return grid_table(std::clamp(least, 0u, most));
  uint32_t side[3] = {0, 0, 0};
  for (const glm::ivec3& e : extents)
    for (int a = 0; a < 3; ++a)
      side[a] = std::max(side[a], bits_for(uint64_t(std::max(e[a], 1)) + 2 * uint64_t(margin)));
  // Flocks share the slots (their cells' slots are their own xor a mix of the flock): room for
  // each, along x and z.
  const uint32_t shared = bits_for(extents.size());
  side[0] += (shared + 1) / 2;
  side[2] += shared / 2;
  constexpr int kWider[3] = {0, 2, 1};  // where spare bits go, in turn
  for (int turn = 0; side[0] + side[1] + side[2] < least; ++turn) ++side[kWider[turn % 3]];
  while (side[0] + side[1] + side[2] > most) {
    int longest = 0;
    for (int a : {2, 1})
      if (side[a] > side[longest]) longest = a;
    --side[longest];
  }
  return {side[0], side[1], side[2]};
}

}  // namespace aeroflock::gpu
