// The neighbour grid's table of occupied cells on the device (grid.glsl: grid_slot): a cell's
// slot is its coordinates modulo the table's sides, 2^x by 2^y by 2^z cells, its flock mixed in.
// A flock's cells nearer than a side apart never share a slot, so a flock the sides hold, with the
// cells its birds search round it, finds its cells at the first look but where another flock's,
// mixed in, take their slots; where they do not hold it (a straggler past the percentiles below,
// a search reaching far, a flock wider than the room), two cells meet in a slot and a search must
// look again (flock.glsl: cell_birds), at twice the cost on lavapipe.
// The host fits the sides to the flocks as they fly (GpuSimulation::submit_frames).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "gpu/host_device.h"

namespace aeroflock::gpu {

struct GridTable {
  uint32_t x = 0, y = 0, z = 0;  // each side's bits
  uint32_t bits() const { return x + y + z; }
  uint32_t slots() const { return 1u << bits(); }
  uint32_t packed() const { return x | (y << 8) | (z << 16); }  // StepConstants::grid_bits
  bool operator==(const GridTable&) const = default;
};

// The sides that suit flocks of no known shape, for `bits` bits: y's a third of them less 4 (a
// flock is flatter than it is wide), x's and z's the rest (x the larger).
GridTable grid_table(uint32_t bits);

// The cells a grid of cells of `cell` cm each flock's birds in `birds` spans, along x, y and z:
// from the 1st to the 99th percentile of its flying birds that flock (a straggler far off would
// widen its table for nothing), at most `samples` of them a flock. One per flock of the `flocks`
// that has any, in flock order.
std::vector<glm::ivec3> flock_extents(std::span<const GpuBird> birds, double cell, uint32_t flocks,
                                      uint32_t samples = 4096);

// The sides for flocks spanning `extents` cells, each side to hold the widest flock and
// `margin` cells either side of it (the cells its outermost birds search), a bit more for each
// doubling of the flocks (they share the slots): between `least` and `most` bits in all. More
// bits than the flocks need go to x, z and y in turn; fewer than they need are taken from the
// longest side first.
GridTable grid_table_for(std::span<const glm::ivec3> extents, int margin, uint32_t least,
                         uint32_t most);

}  // namespace aeroflock::gpu
