#include "model/flock_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "model/cell_grid.h"

namespace aeroflock {
namespace {

bool is_finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The birds in cells of `cell` cm, for the metrics (the perception has its own grid).
CellGrid bird_grid(const std::vector<BirdState>& birds, const std::vector<uint32_t>& members,
                   double cell) {
  CellGrid grid(cell);
  for (uint32_t i : members) grid.insert(birds[i].position, i);
  return grid;
}

std::vector<uint32_t> finite_members(const std::vector<BirdState>& birds,
                                     const std::vector<uint32_t>& members) {
  std::vector<uint32_t> out;
  if (members.empty()) {
    for (uint32_t i = 0; i < birds.size(); ++i)
      if (is_finite(birds[i])) out.push_back(i);
  } else {
    for (uint32_t i : members)
      if (is_finite(birds[i])) out.push_back(i);
  }
  return out;
}

uint32_t root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

bool is_finite(const BirdState& bird) {
  const glm::dquat& q = bird.attitude;
  return bird.mode != FlightMode::quarantined && is_finite(bird.position) &&
         is_finite(bird.velocity) && std::isfinite(q.w) && std::isfinite(q.x) &&
         std::isfinite(q.y) && std::isfinite(q.z);
}

FlockExtent flock_extent(const std::vector<BirdState>& birds) {
  FlockExtent e;
  for (const BirdState& b : birds)
    if (is_finite(b)) e.centre += b.position, e.mean_velocity += b.velocity, ++e.finite;
  if (e.finite == 0) return e;
  e.centre /= double(e.finite);
  e.mean_velocity /= double(e.finite);
  double spread = 0.0;
  for (const BirdState& b : birds)
    if (is_finite(b)) {
      const double d = glm::distance(b.position, e.centre);
      e.radius = std::max(e.radius, d);
      spread += d * d;
    }
  e.rms_radius = std::sqrt(spread / double(e.finite));
  return e;
}

FlockCore flock_core(const std::vector<BirdState>& birds, double fraction, uint32_t flock) {
  FlockCore core;
  std::vector<glm::dvec3> p, v;
  p.reserve(birds.size());
  v.reserve(birds.size());
  for (const BirdState& b : birds)
    if (is_finite(b) && (flock == kAnyFlock || b.flock == flock))
      p.push_back(b.position), v.push_back(b.velocity);
  core.finite = p.size();
  if (p.empty()) return core;
  // The k-th smallest of n values (n > 0), reordering `v`.
  auto kth = [](std::vector<double>& v, size_t k) {
    std::nth_element(v.begin(), v.begin() + ptrdiff_t(k), v.end());
    return v[k];
  };
  std::vector<double> d(p.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t i = 0; i < p.size(); ++i) d[i] = p[i][axis];
    core.centre[axis] = kth(d, d.size() / 2);
  }
  for (size_t i = 0; i < p.size(); ++i) d[i] = glm::distance(p[i], core.centre);
  const double k = std::ceil(std::clamp(fraction, 0.0, 1.0) * double(d.size())) - 1.0;
  core.radius = kth(d, size_t(std::max(k, 0.0)));
  size_t within = 0;
  for (size_t i = 0; i < p.size(); ++i)
    if (glm::distance(p[i], core.centre) <= core.radius) core.velocity += v[i], ++within;
  core.velocity /= double(std::max<size_t>(within, 1));
  return core;
}

namespace {

// Each of the `finite` birds' distance to its nearest other, found through `map` (of those birds).
std::vector<double> nearest_in(const std::vector<BirdState>& birds,
                               const std::vector<uint32_t>& finite, const CellGrid& map) {
  std::vector<double> out(finite.size(), std::numeric_limits<double>::infinity());
  if (finite.size() < 2) return out;
#pragma omp parallel for schedule(dynamic, 64)
  for (int64_t n = 0; n < static_cast<int64_t>(finite.size()); ++n) {
    const uint32_t i = finite[static_cast<size_t>(n)];
    double best = std::numeric_limits<double>::infinity();
    // Ring by ring until no farther cell can hold a nearer bird; then, if still none, all of them.
    for (int r = 1; r <= 8; ++r) {
      map.around(birds[i].position, r, [&](uint32_t j) {
        if (j != i) best = std::min(best, glm::distance(birds[i].position, birds[j].position));
      });
      if (best <= r * map.cell()) break;
    }
    if (!std::isfinite(best) || best > 8 * map.cell())
      for (uint32_t j : finite)
        if (j != i) best = std::min(best, glm::distance(birds[i].position, birds[j].position));
    out[static_cast<size_t>(n)] = best;
  }
  return out;
}

}  // namespace

std::vector<double> nearest_distances(const std::vector<BirdState>& birds,
                                      const std::vector<uint32_t>& members) {
  const std::vector<uint32_t> finite = finite_members(birds, members);
  return nearest_in(birds, finite, bird_grid(birds, finite, kClusterLink));
}

FlockMetrics flock_metrics(const std::vector<BirdState>& birds, const std::vector<Species>& species,
                           const std::vector<uint32_t>& members) {
  FlockMetrics m;
  const std::vector<uint32_t> finite = finite_members(birds, members);
  m.birds = finite.size();
  if (finite.empty()) return m;
  glm::dvec3 heading{0.0};
  for (uint32_t i : finite)
    if (glm::length(birds[i].velocity) > 0.0) heading += glm::normalize(birds[i].velocity);
  m.polarisation = glm::length(heading) / double(finite.size());
  m.largest_cluster = 1.0;
  if (finite.size() < 2) return m;

  // One map of the birds in cells of the cluster link serves the nearest distances and the
  // clusters.
  const CellGrid map = bird_grid(birds, finite, kClusterLink);
  std::vector<double> nearest = nearest_in(birds, finite, map);
  size_t close = 0;
  for (size_t n = 0; n < finite.size(); ++n)
    if (nearest[n] < 0.5 * species[birds[finite[n]].species].box_c) ++close;
  m.too_close = double(close) / double(finite.size());
  const auto middle = nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2);
  std::nth_element(nearest.begin(), middle, nearest.end());
  m.median_nearest = *middle;
  if (nearest.size() % 2 == 0)
    m.median_nearest = 0.5 * (m.median_nearest + *std::max_element(nearest.begin(), middle));

  // Clusters: birds linked within kClusterLink, by union-find over the cells around each bird.
  std::vector<uint32_t> parent(birds.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (uint32_t i : finite)
    map.around(birds[i].position, 1, [&](uint32_t j) {
      if (j > i && glm::distance(birds[i].position, birds[j].position) <= kClusterLink)
        parent[root(parent, i)] = root(parent, j);
    });
  std::unordered_map<uint32_t, size_t> size;
  size_t largest = 0;
  for (uint32_t i : finite) largest = std::max(largest, ++size[root(parent, i)]);
  m.largest_cluster = double(largest) / double(finite.size());
  return m;
}

}  // namespace aeroflock
