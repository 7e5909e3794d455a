#include "model/flock_structure.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "model/cell_grid.h"
#include "model/flock.h"
#include "model/flock_geometry.h"
#include "model/statistics.h"

namespace aeroflock {
namespace {

using glm::dvec3;

// The points in cells about as wide as the space each point has: the bounding box's volume per
// point (each edge at least a millionth of the longest, so that a flat flock has a volume and
// the cells' indices stay small), counted from the box's corner; at least `least` cm.
CellGrid point_grid(std::span<const dvec3> points, double least = 0.0) {
  dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
  for (const dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const dvec3 edge = hi - lo;
  const double longest = std::max({edge.x, edge.y, edge.z, 1e-3});
  const dvec3 e = glm::max(edge, dvec3{1e-6 * longest});
  const double cell = std::cbrt(e.x * e.y * e.z / double(points.size()));
  CellGrid grid(std::max({cell, least, 1e-6 * longest}), lo);
  for (uint32_t i = 0; i < points.size(); ++i) grid.insert(points[i], i);
  return grid;
}

// Whether direction u keeps a ball of radius R centred at p + R u clear of every neighbour:
// u . n_j <= h_j for each (n_j the unit offset to neighbour j, h_j = |offset| / 2R).
bool clear(const dvec3& u, const std::vector<dvec3>& n, const std::vector<double>& h) {
  for (size_t j = 0; j < n.size(); ++j)
    if (glm::dot(u, n[j]) > h[j] + 1e-9) return false;
  return true;
}

// Any unit vector perpendicular to unit n.
dvec3 perpendicular(const dvec3& n) {
  const dvec3 other = std::fabs(n.x) < 0.6 ? dvec3{1, 0, 0} : dvec3{0, 1, 0};
  return glm::normalize(glm::cross(n, other));
}

// Whether the caps of the neighbours n, h (nearest first) leave a direction clear: one on a cap's
// circle, or where two circles cross, if any is (the clear region's boundary is made of them).
bool any_clear(const std::vector<dvec3>& n, const std::vector<double>& h) {
  if (n.empty()) return true;
  for (size_t a = 0; a < n.size(); ++a) {
    if (clear(h[a] * n[a] + std::sqrt(1.0 - h[a] * h[a]) * perpendicular(n[a]), n, h)) return true;
    for (size_t b = a + 1; b < n.size(); ++b) {
      const double g = glm::dot(n[a], n[b]);
      const dvec3 axis = glm::cross(n[a], n[b]);
      const double axis2 = glm::dot(axis, axis);
      if (axis2 < 1e-12) continue;  // the same or opposite circles' centres: no single crossing
      const double ca = (h[a] - g * h[b]) / (1.0 - g * g), cb = (h[b] - g * h[a]) / (1.0 - g * g);
      const dvec3 base = ca * n[a] + cb * n[b];
      const double rest = 1.0 - glm::dot(base, base);
      if (rest < 0.0) continue;  // the circles do not cross
      const dvec3 off = std::sqrt(rest / axis2) * axis;
      if (clear(base + off, n, h) || clear(base - off, n, h)) return true;
    }
  }
  return false;
}

bool exposed(std::span<const dvec3> points, const CellGrid& grid, uint32_t i, double radius) {
  std::vector<std::pair<double, dvec3>> near;
  const int rings = int(std::ceil(2.0 * radius / grid.cell()));
  grid.around(points[i], rings, [&](uint32_t j) {
    const dvec3 d = points[j] - points[i];
    const double r = glm::length(d);
    if (j == i || r == 0.0 || r >= 2.0 * radius) return;  // a ball through p never holds these
    near.push_back({r, d / r});
  });
  std::sort(near.begin(), near.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  // Fewer neighbours leave more clear: the nearest 16, 32, ... first, so that an inner bird is
  // settled by its nearest few (the test costs the cube of their number).
  for (size_t take = std::min<size_t>(16, near.size());; take = std::min(2 * take, near.size())) {
    std::vector<dvec3> n;
    std::vector<double> h;
    for (size_t k = 0; k < take; ++k) {
      n.push_back(near[k].second);
      h.push_back(near[k].first / (2.0 * radius));
    }
    if (!any_clear(n, h)) return false;
    if (take == near.size()) return true;
  }
}

}  // namespace

SymmetricEigen symmetric_eigen(const glm::dmat3& m) {
  // Cyclic Jacobi: rotations zero the off-diagonal terms; a(c)(r) is column c, row r (GLM).
  glm::dmat3 a = m, v(1.0);
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * scale || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        glm::dmat3 r(1.0);
        r[p][p] = c, r[q][q] = c, r[q][p] = s, r[p][q] = -s;
        a = glm::transpose(r) * a * r;
        v = v * r;
      }
  }
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int x, int y) { return a[x][x] < a[y][y]; });
  SymmetricEigen e;
  for (int k = 0; k < 3; ++k) {
    e.value[k] = a[order[k]][order[k]];
    e.vector[size_t(k)] = glm::normalize(v[order[k]]);
  }
  return e;
}

namespace {

// The k points of `points` (in `grid`) nearest to p, nearest first (ties by index), leaving out
// point `self` (none: an index past the end); fewer when there are not k others. Ring by ring,
// until the k-th found is nearer than any point not yet looked at; a straggler far from the rest
// looks at all of them.
std::vector<std::pair<double, uint32_t>> nearest_to(std::span<const dvec3> points,
                                                    const CellGrid& grid, const dvec3& p, size_t k,
                                                    uint32_t self) {
  std::vector<std::pair<double, uint32_t>> found;
  const auto take = [&](uint32_t j) {
    if (j != self) found.push_back({glm::distance(p, points[j]), j});
  };
  bool done = false;
  for (int r = 1; r <= 8 && !done; ++r) {
    found.clear();
    grid.around(p, r, take);
    if (found.size() < k) continue;
    std::nth_element(found.begin(), found.begin() + ptrdiff_t(k - 1), found.end());
    done = found[k - 1].first <= r * grid.cell();
  }
  if (!done) {
    found.clear();
    for (uint32_t j = 0; j < points.size(); ++j) take(j);
  }
  std::sort(found.begin(), found.end());
  if (found.size() > k) found.resize(k);
  return found;
}

}  // namespace

std::vector<uint32_t> k_nearest(std::span<const dvec3> points, size_t k) {
  const size_t count = points.size();
  if (k == 0 || count <= k) return {};
  const CellGrid grid = point_grid(points);
  std::vector<uint32_t> out(count * k);
#pragma omp parallel for schedule(dynamic, 64)
  for (int64_t s = 0; s < int64_t(count); ++s) {
    const auto i = uint32_t(s);
    const auto found = nearest_to(points, grid, points[i], k, i);
    for (size_t m = 0; m < k; ++m) out[size_t(i) * k + m] = found[m].second;
  }
  return out;
}

std::vector<bool> alpha_exposed(std::span<const dvec3> points, double radius) {
  std::vector<char> out(points.size(), 0);
  if (points.empty()) return {};
  const CellGrid grid = point_grid(points, radius);
#pragma omp parallel for schedule(dynamic, 64)
  for (int64_t s = 0; s < int64_t(points.size()); ++s)
    out[size_t(s)] = exposed(points, grid, uint32_t(s), radius);
  return {out.begin(), out.end()};
}

namespace {

// flock_structure with the border's ball `ball(r1)` cm for the flock's median r1.
template <class Ball>
FlockStructure structure_of(std::span<const dvec3> positions, std::span<const dvec3> velocities,
                            Ball ball) {
  FlockStructure f;
  const size_t n = positions.size();
  if (velocities.size() != n)
    throw std::invalid_argument("flock_structure: " + std::to_string(n) + " positions but " +
                                std::to_string(velocities.size()) + " velocities");
  f.birds = n;
  // What cannot be measured is NaN (no motion, too few birds or no internal ones for a rank).
  constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  f.anisotropy.fill(kNone);
  if (n < 2) return f;

  // Principal axes: the eigenvectors of the positions' covariance.
  dvec3 centre{0.0}, velocity{0.0};
  for (size_t i = 0; i < n; ++i) centre += positions[i], velocity += velocities[i];
  centre /= double(n);
  glm::dmat3 covariance(0.0);
  for (const dvec3& p : positions) covariance += glm::outerProduct(p - centre, p - centre);
  const SymmetricEigen shape = symmetric_eigen(covariance / double(n));
  f.axis = shape.vector;
  const bool moving = glm::length(velocity) > 0.0;
  f.motion = moving ? glm::normalize(velocity) : dvec3{0.0};
  for (int k = 0; k < 3; ++k) {
    f.size[k] = 2.0 * std::sqrt(5.0 * std::max(shape.value[k], 0.0));
    f.motion_on_axes[k] = moving ? std::fabs(glm::dot(f.motion, f.axis[size_t(k)])) : kNone;
  }
  f.thinnest_from_vertical = std::acos(std::min(1.0, std::fabs(f.axis[0].y)));

  // Each bird's neighbours, nearest first.
  const size_t ranks = std::min(kStructureRanks, n - 1);
  const std::vector<uint32_t> near = k_nearest(positions, ranks);
  std::vector<double> r1(n);
  double along = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const dvec3 d = positions[near[i * ranks]] - positions[i];
    r1[i] = glm::length(d);
    if (r1[i] > 0.0) along += std::pow(glm::dot(d / r1[i], f.motion), 2);
  }
  f.median_nearest = median(r1);
  f.nearest_along_motion = moving ? along / double(n) : kNone;
  const double border_radius = f.border_radius = ball(f.median_nearest);

  // The border, its birds' spacing against the rest, and each bird's distance from it.
  const std::vector<bool> border = alpha_exposed(positions, border_radius);
  std::vector<double> at_border, inside;
  std::vector<dvec3> border_points;
  for (size_t i = 0; i < n; ++i) {
    (border[i] ? at_border : inside).push_back(r1[i]);
    if (border[i]) border_points.push_back(positions[i]);
  }
  f.border = at_border.size();
  f.border_nearest = at_border.empty() ? kNone : median(at_border);
  f.interior_nearest = inside.empty() ? kNone : median(inside);
  // Each bird's distance to the nearest border bird, through a grid of them.
  std::vector<double> from_border(n, std::numeric_limits<double>::infinity());
  if (!border_points.empty()) {
    const CellGrid border_grid = point_grid(border_points);
#pragma omp parallel for schedule(dynamic, 64)
    for (int64_t s = 0; s < int64_t(n); ++s)
      from_border[size_t(s)] =
          nearest_to(border_points, border_grid, positions[size_t(s)], 1, UINT32_MAX)[0].first;
  }

  // gamma(n) over the internal birds.
  for (size_t rank = 0; rank < ranks; ++rank) {
    glm::dmat3 m(0.0);
    size_t counted = 0;
    for (size_t i = 0; i < n; ++i) {
      const dvec3 d = positions[near[i * ranks + rank]] - positions[i];
      const double r = glm::length(d);
      if (r == 0.0 || r >= from_border[i]) continue;
      m += glm::outerProduct(d / r, d / r);
      ++counted;
    }
    f.internal[rank] = counted;
    if (counted == 0 || !moving) continue;
    const dvec3 w = symmetric_eigen(m / double(counted)).vector[0];
    f.anisotropy[rank] = std::pow(glm::dot(w, f.motion), 2);
  }
  return f;
}

}  // namespace

FlockStructure flock_structure(std::span<const dvec3> positions, std::span<const dvec3> velocities,
                               double border_radius) {
  return structure_of(positions, velocities, [=](double) { return border_radius; });
}

FlockStructure flock_structure_by_spacing(std::span<const dvec3> positions,
                                          std::span<const dvec3> velocities, double border_r1) {
  return structure_of(positions, velocities, [=](double r1) { return border_r1 * r1; });
}

StructureFigures structure_figures(const FlockStructure& f, double wingspan) {
  StructureFigures s;
  s.birds = double(f.birds);
  if (f.birds < 2) return s;
  s.median_nearest = f.median_nearest;
  s.median_nearest_wingspans = f.median_nearest / wingspan;
  s.thickness = f.size[0], s.width = f.size[1], s.length = f.size[2];
  if (f.size[2] > 0.0) {
    s.thickness_over_length = f.size[0] / f.size[2];
    s.width_over_length = f.size[1] / f.size[2];
  }
  s.thinnest_from_vertical = f.thinnest_from_vertical;
  s.motion_on_axes = f.motion_on_axes;
  s.border_fraction = double(f.border) / double(f.birds);
  s.border_over_interior = f.interior_nearest > 0.0 ? f.border_nearest / f.interior_nearest
                                                    : std::numeric_limits<double>::quiet_NaN();
  s.anisotropy = f.anisotropy;
  s.nearest_along_motion = f.nearest_along_motion;
  return s;
}

std::optional<StructureFigures> measure_structure(const Scenario& scenario,
                                                  const std::vector<BirdState>& birds,
                                                  uint32_t flock) {
  std::vector<dvec3> position, velocity;
  for (const BirdState& b : birds)
    if (b.flock == flock && flocks_now(b) && is_finite(b))
      position.push_back(b.position), velocity.push_back(b.velocity);
  if (position.size() < 2) return std::nullopt;
  const FlockStructure f = flock_structure_by_spacing(position, velocity, kBorderBallNearest);
  return structure_figures(f, scenario.species[scenario.flocks[flock].species].box_c);
}

void StructureMean::add(const StructureFigures& f, double time) {
  if (samples == 0) first = time;
  last = time;
  ++samples;
  // Every figure is a double or an array of them: summed member by member over the snapshots that
  // measured it (a NaN is a figure not measured), then divided.
  auto each = [](StructureFigures& a, StructureFigures& b, const StructureFigures& c, auto op) {
    op(a.birds, b.birds, c.birds);
    op(a.median_nearest, b.median_nearest, c.median_nearest);
    op(a.median_nearest_wingspans, b.median_nearest_wingspans, c.median_nearest_wingspans);
    op(a.thickness, b.thickness, c.thickness), op(a.width, b.width, c.width);
    op(a.length, b.length, c.length);
    op(a.thickness_over_length, b.thickness_over_length, c.thickness_over_length);
    op(a.width_over_length, b.width_over_length, c.width_over_length);
    op(a.thinnest_from_vertical, b.thinnest_from_vertical, c.thinnest_from_vertical);
    for (int k = 0; k < 3; ++k) op(a.motion_on_axes[k], b.motion_on_axes[k], c.motion_on_axes[k]);
    op(a.border_fraction, b.border_fraction, c.border_fraction);
    op(a.border_over_interior, b.border_over_interior, c.border_over_interior);
    for (size_t k = 0; k < kStructureRanks; ++k)
      op(a.anisotropy[k], b.anisotropy[k], c.anisotropy[k]);
    op(a.nearest_along_motion, b.nearest_along_motion, c.nearest_along_motion);
  };
  each(sum_, measured_, f, [](double& sum, double& count, double x) {
    if (!std::isnan(x)) sum += x, count += 1.0;
  });
  each(mean, measured_, sum_, [](double& mean, double& count, double sum) {
    mean = count > 0.0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
  });
}

}  // namespace aeroflock
