// The structure of a flock as the field measures starlings (docs/FIELD.md): its shape along its
// principal axes, where its border is and how dense it is there, and how its birds' nearest
// neighbours lie about the direction of motion. Ballerini et al. 2008, Anim. Behav. 76:201
// ("2008a") and PNAS 105:1232 ("2008b"). Pure geometry of one snapshot of positions and
// velocities: the run's observer (run/structure.h) and the tests call the same code.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "model/bird.h"
#include "model/formation_figures.h"
#include "model/scenario.h"

namespace aeroflock {

// gamma(n) is measured for the n-th neighbour, n = 1 .. kStructureRanks (2008b: to about 10).
inline constexpr size_t kStructureRanks = 10;
// The alpha shape's ball that draws the border, in median nearest-neighbour distances
// (docs/FIELD.md "The measures").
inline constexpr double kBorderBallNearest = 3.0;

// A symmetric 3x3 matrix's eigenvalues, smallest first, and their unit eigenvectors (Jacobi).
struct SymmetricEigen {
  glm::dvec3 value{0.0};
  std::array<glm::dvec3, 3> vector{};
};
SymmetricEigen symmetric_eigen(const glm::dmat3& m);

// Each point's k nearest others, nearest first (ties by index), flattened: point i's are at
// [i k, (i + 1) k). Fewer than k + 1 points: empty.
std::vector<uint32_t> k_nearest(std::span<const glm::dvec3> points, size_t k);

// The border as 2008a draws it, with an alpha shape: a point is on the border when a ball of
// radius `radius` touches it with no other point inside (an empty ball: the point is alpha-exposed;
// Edelsbrunner and Mucke 1994). Exact: the balls through the point that exclude a neighbour q leave
// out a cap of the sphere of directions; the point is exposed when the caps of its neighbours
// within 2 radius do not cover that sphere, which is seen at the caps' boundary circles and where
// they cross.
std::vector<bool> alpha_exposed(std::span<const glm::dvec3> points, double radius);

struct FlockStructure {
  size_t birds = 0;
  double median_nearest = 0.0;  // cm: the median of each bird's distance to its nearest (r1)
  // The principal axes (2008a): the eigenvectors of the positions' covariance, thinnest first, and
  // the flock's size along each (cm), thickness I1 <= width I2 <= length I3: the diameters of the
  // uniform ellipsoid of the same second moments, 2 sqrt(5 lambda) (as Young et al. 2013 read the
  // same data; a straggler or two barely move them, as they would the extents).
  std::array<glm::dvec3, 3> axis{};
  glm::dvec3 size{0.0};
  double thinnest_from_vertical = 0.0;  // rad: the angle between the I1 axis and the vertical
  glm::dvec3 motion{0.0};  // unit: the direction of the flock's mean velocity (0: it has none)
  glm::dvec3 motion_on_axes{
      0.0};  // |cos| of the angle between the motion and each axis (NaN: none)
  // The border: alpha-exposed birds (alpha_exposed) for a ball of `border_radius`.
  double border_radius = 0.0;  // cm
  size_t border = 0;
  double border_nearest = 0.0;    // cm: median r1 of the border birds (NaN: none)
  double interior_nearest = 0.0;  // cm: median r1 of the others (NaN: none)
  // The anisotropy factor gamma(n) = (W . V)^2 (2008b): W the eigenvector of the smallest
  // eigenvalue of M = mean over the internal birds of u u^T, u the unit vector to a bird's n-th
  // neighbour (its direction of least crowding), V `motion`. 1/3 when the neighbours lie alike in
  // every direction; above where they lack along the motion. Internal: the birds nearer their n-th
  // neighbour than the border (the nearest border bird), so that the border's empty side biases
  // nothing; internal[n - 1] birds counted (0: gamma NaN, no measure).
  std::array<double, kStructureRanks> anisotropy{};
  std::array<size_t, kStructureRanks> internal{};
  // The mean over all birds of the squared cosine between the direction to the nearest neighbour
  // and the motion: 1/3 when isotropic, below where neighbours lack ahead and behind (NaN: no
  // motion).
  double nearest_along_motion = 0.0;
};

// One snapshot of a flock (positions in cm, velocities in cm/s, both of the same birds: else
// std::invalid_argument), its border drawn with a ball of `border_radius` cm. NaN where a figure
// cannot be measured (FlockStructure's comments).
FlockStructure flock_structure(std::span<const glm::dvec3> positions,
                               std::span<const glm::dvec3> velocities, double border_radius);
// The same with a ball of `border_r1` times the snapshot's median r1 (kBorderBallNearest: as the
// field draws it).
FlockStructure flock_structure_by_spacing(std::span<const glm::dvec3> positions,
                                          std::span<const glm::dvec3> velocities, double border_r1);

// The figures the field reports, of one snapshot or averaged over several (each snapshot's figure,
// then their mean: as 2008a and 2008b average over flocks). Lengths in cm and in the species'
// wingspans (its box_c). NaN: not measured (the motion's figures of a flock at rest, gamma(n) with
// no internal bird, the border's density with no bird inside it).
struct StructureFigures {
  double birds = 0.0;
  double median_nearest = 0.0;                        // cm
  double median_nearest_wingspans = 0.0;              // r1 / wingspan
  double thickness = 0.0, width = 0.0, length = 0.0;  // I1 <= I2 <= I3, cm
  double thickness_over_length = 0.0;                 // I1 / I3
  double width_over_length = 0.0;                     // I2 / I3
  double thinnest_from_vertical = 0.0;                // rad
  glm::dvec3 motion_on_axes{0.0};     // |cos| with the thickness, width and length axes
  double border_fraction = 0.0;       // border birds / birds
  double border_over_interior = 0.0;  // median r1 at the border / inside (< 1: denser border)
  std::array<double, kStructureRanks> anisotropy{};  // gamma(n)
  double nearest_along_motion = 0.0;
};
StructureFigures structure_figures(const FlockStructure& f, double wingspan);

// The mean of several snapshots' figures, each over the snapshots that measured it (NaN where
// none did).
struct StructureMean {
  size_t samples = 0;
  double first = 0.0, last = 0.0;  // s: when the first and the last were taken
  StructureFigures mean;
  void add(const StructureFigures& f, double time);

 private:
  StructureFigures sum_;
  StructureFigures measured_;  // member by member: the snapshots that measured it
};

// The figures of one snapshot of flock `flock` of `scenario`, over its birds that flock now
// (flocks_now) and are finite, the border drawn with a ball of kBorderBallNearest r1; nullopt
// when fewer than two do.
std::optional<StructureFigures> measure_structure(const Scenario& scenario,
                                                  const std::vector<BirdState>& birds,
                                                  uint32_t flock);

// One flock's figures, averaged over a run's snapshots (run/structure.h).
struct FlockStructureSummary {
  std::string flock, species;
  double wingspan = 0.0;  // cm: the species' box_c
  // s: the window asked for, a snapshot at the first frame at or after each from + k every
  double from = 0.0, to = 0.0, every = 0.0;
  StructureMean structure;
  // A flock that meets the wakes or flies in formation (Species::w_formation): its formation at
  // the same snapshots (formation_figures.h), its wings' power over every frame between.
  std::optional<FormationMean> formation;
};

}  // namespace aeroflock
