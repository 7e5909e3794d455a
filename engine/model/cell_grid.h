// Points hashed into cubic cells, for the measures of a flock (flock_geometry.h,
// flock_structure.h): a point's neighbours ring by ring. The perception has its own grid
// (flock.h: NeighbourGrid), the same on both backends.
#pragma once

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace aeroflock {

// Cells of `cell` cm counted from `origin`: an index stays small however far out the points are, as
// long as they lie within 2^31 cells of it.
class CellGrid {
 public:
  explicit CellGrid(double cell, const glm::dvec3& origin = glm::dvec3{0.0})
      : cell_(cell), origin_(origin) {}
  void insert(const glm::dvec3& p, uint32_t index) { cells_[key(cell_of(p))].push_back(index); }
  // Calls f(index) for every point in the cells within `rings` cells of p's (Chebyshev): every
  // point nearer p than rings x cell is among them.
  template <class F>
  void around(const glm::dvec3& p, int rings, F f) const {
    const glm::ivec3 home = cell_of(p);
    for (int dx = -rings; dx <= rings; ++dx)
      for (int dy = -rings; dy <= rings; ++dy)
        for (int dz = -rings; dz <= rings; ++dz) {
          const auto it = cells_.find(key(home + glm::ivec3(dx, dy, dz)));
          if (it != cells_.end())
            for (uint32_t j : it->second) f(j);
        }
  }
  double cell() const { return cell_; }

 private:
  glm::ivec3 cell_of(const glm::dvec3& p) const {
    return glm::ivec3(glm::floor((p - origin_) / cell_));
  }
  static uint64_t key(const glm::ivec3& c) {
    const auto part = [](int v) {
      return static_cast<uint64_t>(static_cast<uint32_t>(v) & 0x1fffffu);
    };
    return part(c.x) | part(c.y) << 21 | part(c.z) << 42;
  }
  double cell_;
  glm::dvec3 origin_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace aeroflock
