// The world cut into slabs along one horizontal axis, one slab per rank (docs/DISTRIBUTED.md).
// Pure arithmetic on whole grid cells, no MPI: which rank owns a bird follows exactly from its
// cell, and every rank computes the same cuts from the same counts.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace aeroflock::dist {

// Birds counted per cell along the axis: (cell, birds), cells ascending, each once.
using CellCounts = std::vector<std::pair<int64_t, uint64_t>>;

struct Slabs {
  int axis = 0;               // 0 (x) or 2 (z): the world's horizontal axis the cuts cross
  double cell = 0.0;          // cm: the neighbour grid's cell; the cuts fall on whole cells
  int64_t halo = 0;           // cells: the largest perception radius, rounded up
  std::vector<int64_t> cuts;  // ranks - 1 of them, nondecreasing: rank r owns the cells
                              // [cuts[r - 1], cuts[r]) (the first from -inf, the last to +inf);
                              // equal cuts leave a rank with none

  int ranks() const { return static_cast<int>(cuts.size()) + 1; }
  int64_t cell_of(const glm::dvec3& position) const;
  int owner(int64_t cell) const;
  bool empty(int rank) const;
  // The ranks other than the owner that hold a cell within `halo` of `cell`: those that see a
  // bird there as a ghost. Appended to `out`, ascending.
  void ghost_ranks(int64_t cell, std::vector<int>& out) const;
};

// The cuts that share `counts` out evenly over `ranks`: each slab at least `halo` cells wide
// (where the flock is too short for all ranks, the last ranks get none).
std::vector<int64_t> balanced_cuts(const CellCounts& counts, int ranks, int64_t halo);
// `now` moved towards balanced_cuts by at most `most` cells each (then kept `halo` apart).
std::vector<int64_t> rebalanced_cuts(const std::vector<int64_t>& now, const CellCounts& counts,
                                     int64_t halo, int64_t most);
// Whether the busiest rank holds more than `tolerance` times the mean.
bool imbalanced(std::span<const uint64_t> birds_per_rank, double tolerance);
// The axis (0: x, 2: z) along which `points` spread the farther.
int longer_axis(std::span<const glm::dvec3> points);
// `counts` merged (several ranks' counts of the same cells added).
CellCounts merged(std::vector<CellCounts> parts);

}  // namespace aeroflock::dist
