// The neighbour grid's table on the device (gpu/grid_table.h): its sides fitted to the flocks as
// they fly, so that a flock's cells, and the cells its outermost birds search, seldom share a
// slot. Needs no device.
#include <gtest/gtest.h>

#include <vector>

#include <glm/vec3.hpp>

#include "gpu/grid_table.h"
#include "gpu/layout.h"

namespace aeroflock::gpu {
namespace {

bool holds(const GridTable& t, const glm::ivec3& extent, int margin) {
  return (1 << t.x) >= extent.x + 2 * margin && (1 << t.y) >= extent.y + 2 * margin &&
         (1 << t.z) >= extent.z + 2 * margin;
}

TEST(GridTable, WithoutFlocksTheSidesAreFlatterThanWide) {
  EXPECT_EQ(grid_table(12), (GridTable{5, 2, 5}));  // 1,000 birds: 4,096 slots
  EXPECT_EQ(grid_table(16), (GridTable{6, 4, 6}));
  EXPECT_EQ(grid_table(10), (GridTable{4, 2, 4}));
  EXPECT_EQ(grid_table(13).bits(), 13u);
  EXPECT_EQ((GridTable{5, 4, 5}).packed(), 5u | (4u << 8) | (5u << 16));
}

TEST(GridTable, SidesHoldTheWidestFlockAndTheCellsItsBirdsSearch) {
  // 1,000 paper starlings of the default scenario in flight: 26 x 9 x 20 cells of 2.56 m. The
  // sides that suit no shape (5, 2, 5) wrap its 9 cells of height every 4: nearly every bird's
  // search met a slot of another cell and searched again.
  const std::vector<glm::ivec3> starlings{{26, 9, 20}};
  EXPECT_FALSE(holds(grid_table(12), starlings[0], 2));
  const GridTable t = grid_table_for(starlings, 2, 12, 14);
  EXPECT_TRUE(holds(t, starlings[0], 2));
  EXPECT_EQ(t, (GridTable{5, 4, 5}));
  // Turned a right angle, it is held as well.
  EXPECT_TRUE(holds(grid_table_for({{{20, 9, 26}}}, 2, 12, 14), {20, 9, 26}, 2));
}

TEST(GridTable, AFlockNeedingFewerBitsThanTheLeastGetsTheRestAlongXZAndY) {
  const GridTable t = grid_table_for({{{4, 2, 4}}}, 2, 12, 16);  // 3 + 3 + 3 bits
  EXPECT_EQ(t.bits(), 12u);
  EXPECT_EQ(t, (GridTable{4, 4, 4}));
  EXPECT_EQ(grid_table_for({{{4, 2, 4}}}, 2, 13, 16), (GridTable{5, 4, 4}));
}

TEST(GridTable, AFlockWiderThanTheRoomLosesItsLongestSidesBitsFirst) {
  // 100 x 10 x 30 cells: 7 + 4 + 6 bits wanted, 14 at most.
  const GridTable t = grid_table_for({{{100, 10, 30}}}, 2, 10, 14);
  EXPECT_EQ(t.bits(), 14u);
  EXPECT_EQ(t, (GridTable{5, 4, 5}));
}

TEST(GridTable, EachDoublingOfTheFlocksGetsABitMore) {
  const GridTable one = grid_table_for({{{26, 9, 20}}}, 2, 10, 20);
  const GridTable two = grid_table_for({{{26, 9, 20}, {3, 2, 3}}}, 2, 10, 20);
  const GridTable five = grid_table_for(std::vector<glm::ivec3>(5, {26, 9, 20}), 2, 10, 20);
  EXPECT_EQ(two.bits(), one.bits() + 1);
  EXPECT_EQ(five.bits(), one.bits() + 3);
  EXPECT_TRUE(holds(five, {26, 9, 20}, 2));
  // No flock: the sides for no shape.
  EXPECT_EQ(grid_table_for({}, 2, 12, 16), grid_table(12));
}

GpuBird flying(const glm::dvec3& position, uint32_t flock) {
  BirdState b;
  b.position = position;
  b.flock = flock;
  b.flocking = 1;
  return pack(b);
}

TEST(GridTable, FlocksSpanTheCellsOfTheirFlyingBirdsAllButTheFarthestStragglers) {
  const double cell = 256.0;
  std::vector<GpuBird> birds;
  // Flock 0: 200 birds over cells 0 to 19 along x, 0 to 3 along y, 0 along z.
  for (int n = 0; n < 200; ++n)
    birds.push_back(flying({cell * (0.1 * n + 0.05), 4096.0 + cell * (n % 4), 10.0}, 0));
  // ...and one straggler 100 cells off: past the 99th percentile.
  birds.push_back(flying({cell * 100.5, 4096.0, 10.0}, 0));
  // Flock 2: two birds on either side of z = 0.
  birds.push_back(flying({10.0, 4096.0, -10.0}, 2));
  birds.push_back(flying({10.0, 4096.0, 10.0 + cell}, 2));
  // Not counted: a perched bird of flock 0, and one that does not flock.
  BirdState perched;
  perched.position = {-cell * 1000.0, 0.0, 0.0};
  perched.flocking = 1;
  perched.mode = FlightMode::perched;
  birds.push_back(pack(perched));
  BirdState alone;
  alone.position = {cell * 1000.0, 0.0, 0.0};
  birds.push_back(pack(alone));
  // Nor one of a flock the scenario does not have (a readback's stale word).
  birds.push_back(flying({0.0, 4096.0, 0.0}, 7));
  const std::vector<glm::ivec3> extents = flock_extents(birds, cell, 3);
  ASSERT_EQ(extents.size(), 2u);
  EXPECT_EQ(extents[0], glm::ivec3(20, 4, 1));
  EXPECT_EQ(extents[1], glm::ivec3(1, 1, 3));  // cells -1 to 1 of z
}

}  // namespace
}  // namespace aeroflock::gpu
