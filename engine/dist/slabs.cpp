#include "slabs.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

namespace aeroflock::dist {

int64_t Slabs::cell_of(const glm::dvec3& position) const {
  return static_cast<int64_t>(std::floor(position[axis] / cell));
}

int Slabs::owner(int64_t c) const {
  return static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), c) - cuts.begin());
}

bool Slabs::empty(int rank) const {
  if (rank == 0 || rank == ranks() - 1) return false;
  return cuts[size_t(rank) - 1] == cuts[size_t(rank)];
}

void Slabs::ghost_ranks(int64_t c, std::vector<int>& out) const {
  const int own = owner(c);
  for (int q = owner(c - halo), last = owner(c + halo); q <= last; ++q)
    if (q != own && !empty(q)) out.push_back(q);
}

namespace {
// `cuts` made nondecreasing with each slab up to `end` at least `halo` wide: a cut that would
// leave a narrower slab moves out to `halo`, and one that passes `end` (the last cell + 1) goes
// to `end`, the ranks after it left with no cells of the flock.
void keep_apart(std::vector<int64_t>& cuts, int64_t first, int64_t end, int64_t halo) {
  int64_t before = first;
  for (int64_t& c : cuts) {
    c = std::max(c, before + halo);
    if (c > end - halo) c = end;
    before = c;
  }
  for (size_t k = 1; k < cuts.size(); ++k) cuts[k] = std::max(cuts[k], cuts[k - 1]);
}
}  // namespace

std::vector<int64_t> balanced_cuts(const CellCounts& counts, int ranks, int64_t halo) {
  std::vector<int64_t> cuts(size_t(std::max(ranks, 1)) - 1, 0);
  if (counts.empty()) return cuts;
  uint64_t total = 0;
  for (const auto& [c, n] : counts) total += n;
  // Cut i before the first cell at which i / ranks of the birds have been passed.
  uint64_t passed = 0;
  size_t k = 0;
  for (size_t i = 0; i < cuts.size(); ++i) {
    const uint64_t target = (total * (i + 1) + uint64_t(ranks) - 1) / uint64_t(ranks);
    while (k < counts.size() && passed < target) passed += counts[k++].second;
    cuts[i] = k < counts.size() ? counts[k].first : counts.back().first + 1;
  }
  keep_apart(cuts, counts.front().first, counts.back().first + 1, halo);
  return cuts;
}

std::vector<int64_t> rebalanced_cuts(const std::vector<int64_t>& now, const CellCounts& counts,
                                     int64_t halo, int64_t most) {
  std::vector<int64_t> cuts = balanced_cuts(counts, static_cast<int>(now.size()) + 1, halo);
  if (counts.empty()) return now;
  for (size_t i = 0; i < cuts.size(); ++i)
    cuts[i] = std::clamp(cuts[i], now[i] - most, now[i] + most);
  keep_apart(cuts, counts.front().first, counts.back().first + 1, halo);
  return cuts;
}

bool imbalanced(std::span<const uint64_t> birds, double tolerance) {
  if (birds.empty()) return false;
  uint64_t total = 0, most = 0;
  for (uint64_t n : birds) total += n, most = std::max(most, n);
  return double(most) * double(birds.size()) > tolerance * double(total);
}

int longer_axis(std::span<const glm::dvec3> points) {
  if (points.empty()) return 0;
  glm::dvec3 lo = points.front(), hi = points.front();
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return hi.z - lo.z > hi.x - lo.x ? 2 : 0;
}

CellCounts merged(std::vector<CellCounts> parts) {
  CellCounts all;
  for (CellCounts& p : parts) all.insert(all.end(), p.begin(), p.end());
  std::sort(all.begin(), all.end());
  CellCounts out;
  for (const auto& [c, n] : all) {
    if (!out.empty() && out.back().first == c)
      out.back().second += n;
    else
      out.emplace_back(c, n);
  }
  return out;
}

}  // namespace aeroflock::dist
