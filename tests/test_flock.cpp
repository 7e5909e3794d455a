// Flocking on the CPU reference (docs/MODEL.md "Flocking"): the neighbour grid against brute force,
// and the criteria of "What a flock must show" on the default scenario's 1,000 starlings.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <glm/geometric.hpp>

#include "flock_run.h"
#include "io/scenario_file.h"
#include "model/body.h"
#include "model/constants.h"
#include "model/flock.h"
#include "model/flock_geometry.h"
#include "model/simulation.h"

namespace aeroflock {
namespace {

using glm::dvec3;
using testing::flocking_bird;

// Every bird's neighbours from the grid equal brute force's, in order, whichever cell the grid
// takes (grid_shape's, and each that grid_cell_for may choose).
void expect_grid_matches_brute_force(const std::vector<BirdState>& birds,
                                     const std::vector<Species>& species, const char* what) {
  std::vector<std::vector<uint32_t>> truth;
  for (uint32_t i = 0; i < birds.size(); ++i)
    truth.push_back(seen_by_brute_force(i, birds, species, dvec3{0.0}));
  GridShape shape = grid_shape(species, birds);
  std::vector<double> cells = grid_cells_allowed(species, birds);
  ASSERT_FALSE(cells.empty());
  EXPECT_NE(std::find(cells.begin(), cells.end(), shape.cell), cells.end()) << what;
  for (const double cell : cells) {
    shape.cell = cell;
    const NeighbourGrid grid(birds, shape);
    size_t seen = 0;
    for (uint32_t i = 0; i < birds.size(); ++i) {
      const std::vector<uint32_t> fast = grid.seen_by(i, species, dvec3{0.0});
      ASSERT_EQ(fast, truth[i]) << what << ", cells of " << cell << " cm: bird " << i;
      seen += fast.size();
    }
    if (birds.size() > 1) {
      EXPECT_GT(seen, 0u) << what << ": nobody saw anybody: nothing was compared";
    }
  }
}

TEST(NeighbourGrid, FindsWhatBruteForceFindsOnRandomFlocks) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Species all_round = starling();
  all_round.separation_all_round = 1;  // its k nearest from all round, the blind sector too
  const std::vector<Species> species = {starling(), eagle(), all_round};
  for (const double size : {500.0, 3000.0, 20000.0}) {  // denser and sparser than the grid's cell
    std::vector<BirdState> birds;
    for (int i = 0; i < 1500; ++i) {
      BirdState b = flocking_bird(size * dvec3{unit(rng), 0.3 * unit(rng), unit(rng)},
                                  1000.0 * glm::normalize(dvec3{1.0, 0.2 * unit(rng), unit(rng)}),
                                  i % 3 == 0 ? 1 : 0);
      b.species = i % 5 == 0 ? 1 : i % 7 == 0 ? 2 : 0;
      if (i % 11 == 0) b.mode = FlightMode::landing;  // neither sees nor is seen
      if (i % 13 == 0) b.flocking = 0;
      birds.push_back(b);
    }
    expect_grid_matches_brute_force(birds, species, "random");
  }
}

// Issue 44: the grid's cell follows how far the searches reach (grid_cell_for). A bird that reached
// R searches about (R / cell + 1)^3 cells and meets about k (1 + cell / R)^3 birds: the cell that
// suits it is about R, and a flock's many dense birds outweigh its few sparse ones.
TEST(NeighbourGrid, TheCellSuitsHowFarTheSearchesReach) {
  const auto at = [](double distance, uint32_t birds) {
    SearchReach r;
    r.count[reach_bin(distance)] = birds;
    return r;
  };
  const std::vector<double> cells = {256.0, 512.0, 1024.0, 2048.0};
  EXPECT_EQ(grid_cell_for(SearchReach{}, cells), 0.0);        // nobody searched: keep the cell
  EXPECT_EQ(grid_cell_for(at(240.0, 1000), cells), 256.0);    // the default's starlings
  EXPECT_EQ(grid_cell_for(at(2000.0, 1000), cells), 2048.0);  // seeing fewer than k in 20 m
  EXPECT_EQ(grid_cell_for(at(700.0, 1000), cells), 512.0);
  SearchReach mixed = at(240.0, 1000);
  mixed.add(at(2000.0, 20));  // and the default's 20 eagles
  EXPECT_EQ(grid_cell_for(mixed, cells), 256.0);
  EXPECT_EQ(grid_cell_for(at(20.0, 5), cells), 256.0);  // never below the least allowed
  // Half octaves from 32 cm; the first and the last bins open.
  EXPECT_EQ(reach_bin(32.0), 0u);
  EXPECT_EQ(reach_bin(1.0), 0u);
  EXPECT_EQ(reach_bin(46.0), 1u);
  EXPECT_EQ(reach_bin(256.0), 6u);
  EXPECT_EQ(reach_bin(1e9), kReachBins - 1);
  // The cells allowed: from a twelfth of the perception (powers of two) to the first past it,
  // grid_shape's among them.
  const std::vector<BirdState> one = {flocking_bird(dvec3{0.0}, dvec3{1000.0, 0.0, 0.0})};
  EXPECT_EQ(grid_cells_allowed({starling()}, one), cells);
  EXPECT_EQ(grid_cells_allowed({goose()}, one), cells);
  EXPECT_EQ(grid_cells_allowed({european_starling()}, one),
            (std::vector<double>{128.0, 256.0, 512.0, 1024.0}));
  EXPECT_EQ(grid_shape({european_starling()}, one).cell, 128.0);
}

// The CPU reference's grid follows them too: geese-migration's 96 geese in three skeins, 80 of them
// seeing fewer than 7 within 20 m, search all their sight; after a second their grid's cells are 20
// m, not grid_shape's 2.56. The default's starlings keep grid_shape's.
TEST(NeighbourGrid, ASparseFlocksCellsGrowADenseFlocksStay) {
  CpuSimulation geese(load_scenario("geese-migration"));
  CpuSimulation starlings(load_scenario("default"));
  while (geese.time() < 1.0) geese.step_frame();
  while (starlings.time() < 1.0) starlings.step_frame();
  EXPECT_EQ(geese.grid_cell(), 2048.0);
  EXPECT_EQ(starlings.grid_cell(), 256.0);
}

TEST(NeighbourGrid, FindsWhatBruteForceFindsOnAdversarialFlocks) {
  const std::vector<Species> species = {starling()};
  const double cell =
      grid_shape(species, {flocking_bird(dvec3{0.0}, dvec3{1000.0, 0.0, 0.0})}).cell;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // All in one cell, more than neighbours can hold, with equal distances (ties by index).
  std::vector<BirdState> one_cell;
  for (int i = 0; i < 300; ++i)
    one_cell.push_back(
        flocking_bird(dvec3{0.25 * cell * unit(rng), 10.0 * (i % 3), 0.25 * cell * unit(rng)},
                      dvec3{1000.0, 0.0, 0.0}));
  for (int i = 0; i < 8; ++i)
    one_cell.push_back(flocking_bird(dvec3{50.0, 400.0, 50.0 * i}, dvec3{0.0, 0.0, 1000.0}));
  expect_grid_matches_brute_force(one_cell, species, "one cell");
  // On the cells' borders and corners, and across them by a hair.
  std::vector<BirdState> borders;
  for (int x = -3; x <= 3; ++x)
    for (int y = -2; y <= 2; ++y)
      for (int z = -3; z <= 3; ++z)
        for (const double hair : {0.0, 1e-9, -1e-9})
          borders.push_back(flocking_bird(cell * dvec3{x, y, z} + hair, dvec3{0.0, 0.0, -1000.0}));
  expect_grid_matches_brute_force(borders, species, "cell borders");
  // Farther apart than the perception radius: nobody sees anybody.
  std::vector<BirdState> apart;
  for (int i = 0; i < 20; ++i)
    apart.push_back(flocking_bird(dvec3{3000.0 * i, 0.0, 0.0}, dvec3{0.0, 0.0, 1000.0}));
  const NeighbourGrid grid(apart, grid_shape(species, apart));
  for (uint32_t i = 0; i < apart.size(); ++i)
    EXPECT_TRUE(grid.seen_by(i, species, dvec3{0.0}).empty());
  // One bird, and none.
  const std::vector<BirdState> one = {flocking_bird(dvec3{0.0}, dvec3{1000.0, 0.0, 0.0})};
  EXPECT_TRUE(NeighbourGrid(one, grid_shape(species, one)).seen_by(0, species, dvec3{0.0}).empty());
  std::vector<Perception> perception;
  perceive({}, species, World{}, 0, 0, 0.03, GridShape{kMinGridCell, 1024}, perception);
  EXPECT_TRUE(perception.empty());
}

TEST(Perception, SeesTheNearestOutsideTheBlindSectorWithinTheRadius) {
  const Species s = starling();
  const dvec3 ahead{1.0, 0.0, 0.0};
  EXPECT_TRUE(sees(s, ahead, dvec3{100.0, 0.0, 0.0}));
  EXPECT_TRUE(sees(s, ahead, dvec3{0.0, 0.0, 100.0}));     // beside
  EXPECT_TRUE(sees(s, ahead, dvec3{-100.0, 0.0, 101.0}));  // 44.7 deg off straight back
  EXPECT_FALSE(sees(s, ahead, dvec3{-100.0, 0.0, 99.0}));  // 44.7 deg: inside the 45
  EXPECT_FALSE(sees(s, ahead, dvec3{-100.0, 0.0, 0.0}));   // straight behind
  EXPECT_FALSE(sees(s, ahead, dvec3{s.perception_radius + 1.0, 0.0, 0.0}));
  // k nearest, nearest first, ties by index.
  std::vector<BirdState> birds = {flocking_bird(dvec3{0.0}, dvec3{1000.0, 0.0, 0.0})};
  for (int i = 1; i <= 10; ++i)
    birds.push_back(flocking_bird(dvec3{100.0 * ((i + 1) / 2), 0.0, 0.0}, dvec3{1000.0, 0.0, 0.0}));
  const std::vector<uint32_t> seen = seen_by_brute_force(0, birds, {s}, dvec3{0.0});
  EXPECT_EQ(seen, (std::vector<uint32_t>{1, 2, 3, 4, 5, 6, 7}));
}

// Issue 41: a species whose separation heeds all round (separation_all_round, StarDisplay's) takes
// its k nearest from all round it, the blind sector too; a bird there pushes its goal away but
// neither turns it (alignment, cohesion) nor changes its airspeed. Without, the same bird is not
// among its k nearest at all.
TEST(Perception, ABirdInTheBlindSectorCountsInTheSeparationAloneWhenItHeedsAllRound) {
  Species s = starling();
  s.separation_all_round = 1;
  const dvec3 ahead{1.0, 0.0, 0.0};
  const dvec3 behind{-100.0, 0.0, 20.0};  // 11 degrees off straight back: inside the blind sector
  EXPECT_TRUE(sees(s, ahead, behind));
  EXPECT_FALSE(outside_blind(s, ahead, behind));
  EXPECT_TRUE(outside_blind(s, ahead, dvec3{0.0, 0.0, 100.0}));
  EXPECT_FALSE(sees(s, ahead, dvec3{-s.perception_radius - 1.0, 0.0, 0.0}));
  // Its 7 nearest: the 3 behind (nearest) and 4 of the 10 ahead; without, the 7 nearest ahead.
  const dvec3 forward{1000.0, 0.0, 0.0};
  std::vector<BirdState> birds = {flocking_bird(dvec3{0.0}, forward)};
  for (int i = 1; i <= 10; ++i) birds.push_back(flocking_bird(dvec3{100.0 * i, 0.0, 0.0}, forward));
  for (int i = 1; i <= 3; ++i) birds.push_back(flocking_bird(dvec3{-50.0 * i, 0.0, 0.0}, forward));
  EXPECT_EQ(seen_by_brute_force(0, birds, {s}, dvec3{0.0}),
            (std::vector<uint32_t>{11, 1, 12, 13, 2, 3, 4}));
  Species sighted = s;
  sighted.separation_all_round = 0;
  EXPECT_EQ(seen_by_brute_force(0, birds, {sighted}, dvec3{0.0}),
            (std::vector<uint32_t>{1, 2, 3, 4, 5, 6, 7}));
  // One close behind in the blind sector, flying faster and to the left: its goal is the route's
  // and the separation's alone, at cruise_speed.
  const std::vector<BirdState> two = {flocking_bird(dvec3{0.0}, forward),
                                      flocking_bird(behind, dvec3{1100.0, 0.0, -500.0})};
  ASSERT_LT(glm::length(behind), s.separation_radius);
  ASSERT_EQ(s.separation_lookahead, 0.0);
  ASSERT_EQ(s.separation_front, 1.0);
  const dvec3 route{10000.0, 0.0, 0.0};
  const Perception p =
      social_goal(s, two[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, two);
  const dvec3 separation =
      -glm::normalize(behind) * std::pow(1.0 - glm::length(behind) / s.separation_radius, 2.0);
  const dvec3 expected =
      glm::normalize(s.w_route * route_heading(s, route, dvec3{0.0}, glm::length(forward)) +
                     s.w_separation * separation);
  EXPECT_EQ(p.neighbours, 1u);
  EXPECT_NEAR(glm::length(p.direction - expected), 0.0, 1e-12);
  EXPECT_LT(p.direction.z, -0.01);  // pushed away from it, to the left
  EXPECT_DOUBLE_EQ(p.airspeed, s.cruise_speed);
  // Outside the blind sector the same bird, beside, turns it to its heading and speeds it up.
  const std::vector<BirdState> beside = {two[0],
                                         flocking_bird(dvec3{0.0, 0.0, 100.0}, two[1].velocity)};
  const Perception q =
      social_goal(s, beside[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, beside);
  EXPECT_GT(q.airspeed, s.cruise_speed);
  EXPECT_LT(q.direction.z, p.direction.z);
  // With one beside, one 6 m behind in the blind sector (beyond separation_radius: no push) changes
  // nothing but the count: neither the cohesion, nor the mean of how much faster they fly (taken
  // over the one beside alone).
  std::vector<BirdState> three = beside;
  three.push_back(flocking_bird(dvec3{-600.0, 0.0, 50.0}, dvec3{1300.0, 0.0, 300.0}));
  ASSERT_GT(zone_distance(s, three[2].position, glm::normalize(forward)), s.separation_radius);
  ASSERT_FALSE(outside_blind(s, glm::normalize(forward), three[2].position));
  const Perception r =
      social_goal(s, three[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1, 2}, three);
  EXPECT_EQ(r.neighbours, 2u);
  EXPECT_EQ(r.direction, q.direction);
  EXPECT_EQ(r.airspeed, q.airspeed);
}

TEST(Perception, SocialGoalSeparatesAlignsAndCoheres) {
  Species s = starling();
  const dvec3 forward{1000.0, 0.0, 0.0};
  // A bird close on the right: the goal turns left (-z) of the route straight ahead; slows.
  std::vector<BirdState> birds = {flocking_bird(dvec3{0.0}, forward),
                                  flocking_bird(dvec3{0.0, 0.0, 50.0}, forward)};
  const dvec3 route{10000.0, 0.0, 0.0};
  Perception p =
      social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds);
  EXPECT_EQ(p.neighbours, 1u);
  EXPECT_NEAR(p.nearest, 50.0, 1e-9);
  EXPECT_LT(p.direction.z, -0.1);
  EXPECT_NEAR(glm::length(p.direction), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.airspeed, s.cruise_speed);  // beside it: neither ahead nor behind
  // A bird far ahead and to the left, flying left: the goal turns left, the bird speeds up.
  birds[1] = flocking_bird(dvec3{1500.0, 0.0, -500.0}, dvec3{700.0, 0.0, -700.0});
  p = social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds);
  EXPECT_LT(p.direction.z, -0.1);
  EXPECT_GT(p.airspeed, s.cruise_speed);
  // One close ahead: it slows.
  birds[1] = flocking_bird(dvec3{50.0, 0.0, 0.0}, forward);
  EXPECT_LT(
      social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds).airspeed,
      s.cruise_speed);
  // One beside flying 2 m/s faster: it speeds up by speed_match x 200 cm/s; slower, it slows.
  ASSERT_GT(s.speed_match, 0.0);
  birds[1] = flocking_bird(dvec3{0.0, 0.0, 500.0}, dvec3{1200.0, 0.0, 0.0});
  EXPECT_NEAR(
      social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds).airspeed,
      std::clamp(s.cruise_speed + s.speed_match * 200.0, s.min_speed, s.max_speed), 1e-9);
  birds[1] = flocking_bird(dvec3{0.0, 0.0, 500.0}, dvec3{800.0, 0.0, 0.0});
  EXPECT_LT(
      social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds).airspeed,
      s.cruise_speed);
  // None seen: no goal.
  EXPECT_EQ(social_goal(s, birds[0], dvec3{0.0}, route, false, {}, birds).neighbours, 0u);
  // One 5 m straight ahead, beyond separation_radius: the cohesion pulls it on through its
  // airspeed as well (issue 39), cruise_speed w_cohesion / (w_route + w_alignment + w_cohesion).
  const dvec3 x{1.0, 0.0, 0.0};
  EXPECT_NEAR(cohesion_pull(s, x, x),
              s.cruise_speed * s.w_cohesion / (s.w_route + s.w_alignment + s.w_cohesion), 1e-9);
  EXPECT_EQ(cohesion_pull(s, dvec3{0.0, 0.0, 1.0}, x), 0.0);  // beside: steering does it
  birds[1] = flocking_bird(dvec3{500.0, 0.0, 0.0}, forward);
  ASSERT_GT(s.separation_radius, 250.0);
  ASSERT_LT(s.separation_radius, 500.0);
  const double pulled = s.cruise_speed +
                        s.speed_gain * 500.0 * (1.0 - s.separation_radius / 500.0) +
                        cohesion_pull(s, x, x);
  ASSERT_LT(pulled, s.max_speed);
  EXPECT_NEAR(
      social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds).airspeed,
      pulled, 1e-9);
  // Its route over (route_over), a bird flies on with its flock: a route to the right turns it
  // right, one beside on the left turns it left once the route no longer counts.
  birds[1] = flocking_bird(dvec3{0.0, 0.0, -500.0}, forward);
  const dvec3 right{0.0, 0.0, 1e6};
  EXPECT_GT(social_goal(s, birds[0], dvec3{0.0}, right, false, std::vector<uint32_t>{1}, birds)
                .direction.z,
            0.0);
  EXPECT_LT(social_goal(s, birds[0], dvec3{0.0}, right, true, std::vector<uint32_t>{1}, birds)
                .direction.z,
            0.0);
}

// The separation zone reaches separation_front times farther along the flight than across it
// (issue 41): a neighbour diagonally ahead or behind, beyond separation_radius but inside the zone,
// pushes the goal away; one beside at the same distance does not; straight ahead or behind, the
// zone's push is along the flight, and steering (which turns the bird across it) ignores it.
TEST(Perception, TheSeparationZoneReachesFartherAlongTheFlight) {
  Species s = starling();
  s.separation_front = 1.5;
  const dvec3 forward{1000.0, 0.0, 0.0};
  const double r = 1.02 * s.separation_radius;  // beyond the zone across, inside it along
  EXPECT_NEAR(zone_distance(s, dvec3{0.0, 0.0, r}, dvec3{1, 0, 0}), r, 1e-9);
  EXPECT_NEAR(zone_distance(s, dvec3{r, 0.0, 0.0}, dvec3{1, 0, 0}), r / s.separation_front, 1e-9);
  const dvec3 route{10000.0, 0.0, 0.0};
  const double c = r / std::sqrt(2.0);
  for (const double along : {c, -c}) {
    std::vector<BirdState> birds = {flocking_bird(dvec3{0.0}, forward),
                                    flocking_bird(dvec3{along, 0.0, c}, forward)};
    s.w_cohesion = 0.0;  // beyond separation_radius its cohesion would pull towards it: off
    const Perception p =
        social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds);
    EXPECT_LT(p.direction.z, -0.01) << "pushed away to the left, neighbour at x " << along;
    birds[1].position = dvec3{0.0, 0.0, r};  // beside, as far: outside the zone
    EXPECT_NEAR(social_goal(s, birds[0], dvec3{0.0}, route, false, std::vector<uint32_t>{1}, birds)
                    .direction.z,
                0.0, 1e-12);
  }
}

// The separation acts where a neighbour will be nearest within separation_lookahead at both
// birds' velocities (issue 41): a bird overtaking one 3 m ahead at 3 m/s steps aside now, not once
// it is inside the zone; one drawing apart, or any without the lookahead, is judged where it is.
TEST(Perception, TheSeparationActsWhereANeighbourClosingFastWillBeNearest) {
  Species s = european_starling();
  s.separation_lookahead = 0.75;
  const dvec3 ahead{300.0, 0.0, 40.0};  // 3 m ahead, 0.4 m to the right
  const dvec3 closing{-300.0, 0.0, 0.0};
  EXPECT_EQ(nearest_offset(s, ahead, closing), (dvec3{75.0, 0.0, 40.0}));       // 0.75 s on
  EXPECT_EQ(nearest_offset(s, ahead, 2.0 * closing), (dvec3{0.0, 0.0, 40.0}));  // nearest at 0.5 s
  EXPECT_EQ(nearest_offset(s, ahead, -closing), ahead);                         // drawing apart
  const dvec3 straight{300.0, 0.0, 0.0};
  EXPECT_EQ(nearest_offset(s, straight, closing), (dvec3{75.0, 0.0, 0.0}))
      << "nearest within the lookahead: 0.75 s on, not at the meeting 1 s on";
  EXPECT_EQ(nearest_offset(s, straight, 2.0 * closing), straight) << "meeting: pushed from here";
  // Meeting head on within the lookahead, the nearest point is a rounding residual of either sign:
  // never one through the neighbour.
  for (const double x : {109.5, 37.3, 251.9})
    for (const double v : {-372.1, -501.7, -333.3})
      EXPECT_GT(glm::dot(nearest_offset(s, dvec3{x, 0.0, 0.0}, dvec3{v, 0.0, 0.0}), dvec3{x, 0, 0}),
                0.0)
          << x << " cm closing at " << v << " cm/s";
  Species off = s;
  off.separation_lookahead = 0.0;
  EXPECT_EQ(nearest_offset(off, ahead, closing), ahead);
  // Its social goal: outside the zone now (zone distance 1.76 m against 1.45 m), inside it 0.75 s
  // on: pushed away from where the neighbour will be, (75, 0, 40).
  s.w_cohesion = s.w_alignment = off.w_cohesion = off.w_alignment = 0.0;
  const std::vector<BirdState> birds = {flocking_bird(dvec3{0.0}, dvec3{1300.0, 0.0, 0.0}),
                                        flocking_bird(ahead, dvec3{1000.0, 0.0, 0.0})};
  const dvec3 route{1e6, 0.0, 0.0};
  const std::vector<uint32_t> seen{1};
  const dvec3 forward{1.0, 0.0, 0.0}, then{75.0, 0.0, 40.0};
  ASSERT_GT(zone_distance(s, ahead, forward), s.separation_radius);
  const double fall = std::pow(1.0 - zone_distance(s, then, forward) / s.separation_radius, 2.0);
  const dvec3 d =
      glm::normalize(s.w_route * forward - s.w_separation * fall * glm::normalize(then));
  EXPECT_NEAR(
      glm::distance(social_goal(s, birds[0], dvec3{0.0}, route, false, seen, birds).direction, d),
      0.0, 1e-12);
  EXPECT_EQ(social_goal(off, birds[0], dvec3{0.0}, route, false, seen, birds).direction, forward);
}

// The route's share of d aims at the route goal's height height_capture ahead (issue 39): far
// from the goal it climbs as steeply towards that height as it would height_capture away;
// nearer than that, straight at the goal.
TEST(Perception, TheRouteAimsAtItsGoalsHeightHeightCaptureAhead) {
  const Species s = starling();
  const dvec3 far{2.5e6, 15000.0, 0.0};  // 25 km on, 150 m up
  const dvec3 u = route_direction(s, far);
  EXPECT_NEAR(u.y / u.x, 15000.0 / s.height_capture, 1e-12);
  const dvec3 near{0.5 * s.height_capture, 1000.0, 0.0};
  EXPECT_NEAR(glm::distance(route_direction(s, near), glm::normalize(near)), 0.0, 1e-12);
}

// In a wind the route's share of d is the heading that holds its track (issue 39): 8 m/s straight
// across at 10 m/s through the air, asin(0.8) = 53.13 degrees into the wind, its climb as it was;
// in calm air, or drifting in full (drift_compensation 0), route_direction's.
TEST(Perception, TheRouteHeadsIntoAWindAcrossItToHoldItsTrack) {
  Species s = starling();
  const dvec3 far{2.5e6, 15000.0, 0.0}, across{0.0, 0.0, 800.0};
  const dvec3 calm = route_direction(s, far);
  EXPECT_NEAR(glm::distance(route_heading(s, far, dvec3{0.0}, 1000.0), calm), 0.0, 1e-12);
  const dvec3 h = route_heading(s, far, across, 1000.0);
  EXPECT_NEAR(std::atan2(-h.z, h.x), std::asin(0.8), 1e-12);
  EXPECT_NEAR(h.y, calm.y, 1e-12);
  EXPECT_NEAR(glm::length(h), 1.0, 1e-12);
  // Its head into that heading's air velocity, 10 m/s: over the ground it flies along the way.
  const dvec3 air = 1000.0 * glm::normalize(horizontal(h));
  EXPECT_NEAR((air + across).z, 0.0, 1e-9);
  s.drift_compensation = 0.0;
  EXPECT_NEAR(glm::distance(route_heading(s, far, across, 1000.0), calm), 0.0, 1e-12);
}

// A flock flies in the air it moves with (issue 39): in a uniform wind every bird sees the same
// birds and steers the same heading through the air, at the same airspeed, as the same flock in
// calm air whose velocities are those less the wind. Taken over the ground, 100 migrants in 8 m/s
// across spread to 45 m and split into two flocks side by side.
TEST(Perception, AFlockInAUniformWindFliesAsInCalmAir) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<Species> species = {starling()};
  const dvec3 wind{300.0, 0.0, 800.0};
  std::vector<BirdState> calm_birds, windy_birds;
  for (int i = 0; i < 300; ++i) {
    const BirdState b =
        flocking_bird(1500.0 * dvec3{unit(rng), 0.3 * unit(rng), unit(rng)},
                      1000.0 * glm::normalize(dvec3{1.0, 0.1 * unit(rng), 0.3 * unit(rng)}));
    calm_birds.push_back(b);
    windy_birds.push_back(b);
    windy_birds.back().velocity += wind;
  }
  const NeighbourGrid calm_grid(calm_birds, grid_shape(species, calm_birds));
  const NeighbourGrid windy_grid(windy_birds, grid_shape(species, windy_birds));
  size_t seen = 0;
  for (uint32_t i = 0; i < calm_birds.size(); ++i) {
    const std::vector<uint32_t> in_calm = calm_grid.seen_by(i, species, dvec3{0.0});
    ASSERT_EQ(windy_grid.seen_by(i, species, wind), in_calm) << "bird " << i;
    seen += in_calm.size();
    // Its route over, the social goal alone.
    const Perception c =
        social_goal(species[0], calm_birds[i], dvec3{0.0}, dvec3{0.0}, true, in_calm, calm_birds);
    const Perception w =
        social_goal(species[0], windy_birds[i], wind, dvec3{0.0}, true, in_calm, windy_birds);
    EXPECT_NEAR(glm::distance(c.direction, w.direction), 0.0, 1e-9) << "bird " << i;
    EXPECT_NEAR(c.airspeed, w.airspeed, 1e-6) << "bird " << i;
  }
  EXPECT_GT(seen, 1000u);
  // Over the ground the same flock would align with other directions: what the wind changed.
  const std::vector<uint32_t> some = calm_grid.seen_by(0, species, dvec3{0.0});
  const Perception over_ground =
      social_goal(species[0], windy_birds[0], dvec3{0.0}, dvec3{0.0}, true, some, windy_birds);
  const Perception in_air =
      social_goal(species[0], windy_birds[0], wind, dvec3{0.0}, true, some, windy_birds);
  EXPECT_GT(glm::distance(over_ground.direction, in_air.direction), 0.05);
}

// docs/MODEL.md "What a flock must show", criteria 1-4, on the CPU reference: the default
// scenario's 1,000 starlings, 60 s after the first 20, every frame. The half-size of the box
// holding `flock`'s birds, each axis.
dvec3 spawn_half_size(const std::vector<BirdState>& birds, uint32_t flock) {
  dvec3 lo(1e300), hi(-1e300);
  for (const BirdState& b : birds)
    if (b.flock == flock) lo = glm::min(lo, b.position), hi = glm::max(hi, b.position);
  return 0.5 * (hi - lo);
}

// --birds N keeps the scenario's density: each flock's spawn box grows with the cube root of its
// share, so 64 times the birds fill a box 4 times as wide, not the same box 64 times as densely.
TEST(Spawn, MoreBirdsKeepTheScenarioDensity) {
  const Scenario s = load_scenario("default");
  ASSERT_EQ(s.flocks[0].name, "starlings");
  const std::vector<BirdState> own = spawn_birds(s);
  const std::vector<BirdState> more = spawn_birds(s, 64 * 1020);
  uint64_t starlings = 0;
  for (const BirdState& b : more) starlings += b.flock == 0;
  EXPECT_EQ(starlings, 64u * 1000u);  // shared in proportion: 1,000 of 1,020
  // Rounded as the largest remainders ask: 200 is 196.08 starlings and 3.92 eagles, so 196 and 4.
  for (const auto& [total, eagles] : {std::pair{200u, 4u}, {1u, 0u}, {51u, 1u}, {1020u, 20u}}) {
    uint32_t seen = 0;
    for (const BirdState& b : spawn_birds(s, total)) seen += b.flock == 1;
    EXPECT_EQ(seen, eagles) << total << " birds";
  }
  const dvec3 small = spawn_half_size(own, 0), large = spawn_half_size(more, 0);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(small[axis], s.flocks[0].spawn_extent[axis], 0.02 * s.flocks[0].spawn_extent[axis]);
    EXPECT_NEAR(large[axis] / small[axis], 4.0, 0.05) << "axis " << axis;
  }
  // The same for one flock resized (--flock starlings=8000): twice as wide, eagles untouched.
  Scenario resized = s;
  resize_flock(resized, 0, 8000);
  const std::vector<BirdState> eight = spawn_birds(resized);
  EXPECT_EQ(eight.size(), 8020u);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(spawn_half_size(eight, 0)[axis] / small[axis], 2.0, 0.05) << "axis " << axis;
  resize_flock(resized, 1, 0);  // no eagles: the flock is gone
  ASSERT_EQ(resized.flocks.size(), 1u);
  EXPECT_EQ(spawn_birds(resized).size(), 8000u);
}

// A flock grown so far that its box would reach the ground keeps the box's height and widens it
// instead: every bird starts above the ground, as dense as the scenario's flock.
TEST(Spawn, AFlockGrownPastTheGroundWidensInstead) {
  Scenario s = load_scenario("default");
  Flock& f = s.flocks[0];
  f.spawn_centre.y = 1000.0;  // 10 m up, its box 3 m high: 100 times the birds would reach -4 m
  const glm::dvec3 own = f.spawn_extent;
  const double density = f.count / (own.x * own.y * own.z);
  const uint32_t grown = 100 * f.count;
  const glm::dvec3 e = spawn_extent(f, s.species[f.species], grown, s.world.ground_height);
  EXPECT_DOUBLE_EQ(e.y, 900.0);  // 90 % of the centre's height above the ground
  EXPECT_NEAR(grown / (e.x * e.y * e.z) / density, 1.0, 1e-9);
  EXPECT_NEAR(e.x / e.z, own.x / own.z, 1e-9);

  resize_flock(s, 0, grown);  // --flock starlings=100000
  EXPECT_NO_THROW(validate(s));
  uint32_t starlings = 0;
  for (const BirdState& b : spawn_birds(s)) {
    if (b.flock != 0) continue;
    ++starlings;
    ASSERT_GT(b.position.y, s.world.ground_height);
  }
  EXPECT_EQ(starlings, grown);
  // --birds N the same way.
  Scenario t = load_scenario("default");
  t.flocks[0].spawn_centre.y = 1000.0;
  for (const BirdState& b : spawn_birds(t, 100 * 1020))
    ASSERT_GT(b.position.y, t.world.ground_height);
}

// docs/MODEL.md's flock criteria and, of the same flight, the field's (docs/FIELD.md).
TEST(FlockCriteria, TheDefaultStarlingsKeepSpacingOrderAndCohesionAndFlyTheRoute) {
  const Scenario scenario = load_scenario("default");
  CpuSimulation sim(scenario);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 20.0, 80.0);
  testing::expect_flock_criteria(run, scenario, 0);
  testing::expect_structure_criteria(run);
}

// Issue 41: the murmuration's real starlings (`european_starling`; 1,000 of its 10,000, at the
// scenario's density) after 30 s of flight: the flock criteria, and the field's spacing in metres
// (docs/FIELD.md).
TEST(FlockCriteria, TheMurmurationsEuropeanStarlingsKeepTheFieldsSpacingInMetres) {
  const Scenario scenario = load_scenario("murmuration");
  CpuSimulation sim(scenario, 1000);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 30.0, 60.0);
  testing::expect_flock_criteria(run, scenario, 0, {.straight_legs = false});
  testing::expect_murmuration_structure(run);
}

// Issue 41's option (`separation_all_round`, StarDisplay's: the k nearest sought all round, the
// blind sector hiding them from all but the separation): the default starlings with it keep the
// flock criteria and their first neighbours lie at their sides (gamma(1) 0.46, 0.09 without),
// gamma falling below 1/3 by the 5th (docs/MODEL.md "Held against the field"; not the preset's
// because on Vulkan the flock grows thicker than 1/3 and a migrating flock longer than 40 m).
TEST(FlockCriteria, WithTheSeparationAllRoundTheDefaultStarlingsFirstNeighboursLieAtTheirSides) {
  Scenario scenario = load_scenario("default");
  Species& s = scenario.species[scenario.flocks[0].species];
  ASSERT_EQ(s.separation_all_round, 0.0);
  s.separation_all_round = 1;
  CpuSimulation sim(scenario);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 20.0, 80.0);
  testing::expect_flock_criteria(run, scenario, 0);
  testing::expect_structure_criteria(run);
  const StructureFigures& m = run.structure.mean;
  EXPECT_GT(m.anisotropy[0], 0.4);
  EXPECT_LT(m.anisotropy[4], 1.0 / 3.0);
  EXPECT_LT(m.nearest_along_motion, 0.35);  // 0.38 without: fewer nearest ahead and behind
}

// Not met (issue 41): real starlings are packed more tightly at their flock's border than in its
// centre (Ballerini et al. 2008a: border r1 / interior r1 0.65-0.82); the murmuration's are not
// (1.15-1.17 with the separation's lookahead, 1.23-1.24 without; a random cloud's 1.05-1.2).
TEST(FlockCriteria, DISABLED_TheMurmurationsEuropeanStarlingsAreDenserAtTheBorder) {
  const Scenario scenario = load_scenario("murmuration");
  CpuSimulation sim(scenario, 1000);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 30.0, 60.0);
  EXPECT_LT(run.structure.mean.border_over_interior, 1.0);
}

// Not met (issue 41): real starlings are packed more tightly at their flock's border than in its
// centre (Ballerini et al. 2008a: border r1 / interior r1 0.65-0.82); ours are not (1.1-1.2, a
// random cloud's 1.05-1.2), whichever of the rules in docs/MODEL.md "Held against the field" we
// tried. Run with --gtest_also_run_disabled_tests.
TEST(FlockCriteria, DISABLED_TheDefaultStarlingsAreDenserAtTheBorderThanInTheCentre) {
  const Scenario scenario = load_scenario("default");
  CpuSimulation sim(scenario);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 20.0, 80.0);
  EXPECT_LT(run.structure.mean.border_over_interior, 1.0);
}

// Not met (issue 41): a starling's first neighbours lie at its sides, gamma(1) 0.8-0.85, falling to
// 1/3 by the 6th-7th (Ballerini et al. 2008b), held as the murmuration's are
// (expect_field_anisotropy). Ours lie ahead and behind (gamma(1) 0.09); a separation zone 1.5
// times longer along the flight (`separation_front`) gives 0.50 and fails the flock's spacing; the
// separation all round (`separation_all_round`) gives 0.46 with gamma(7) 0.20-0.24 (the bound
// 0.233), and on Vulkan a flock at the thin bound (I1 / I3 0.30-0.34, seeds 1-4) and a
// migrating flock 49 m long, 40 m the bound (docs/MODEL.md "Held against the field").
TEST(FlockCriteria, DISABLED_TheDefaultStarlingsFirstNeighboursLieAtTheirSides) {
  const Scenario scenario = load_scenario("default");
  CpuSimulation sim(scenario);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 20.0, 80.0);
  testing::expect_field_anisotropy(run.structure.mean);
}

// Criterion 5: the same flock with flocking off fails spacing or cohesion.
TEST(FlockCriteria, WithFlockingOffTheSameStarlingsFailSpacingOrCohesion) {
  Scenario scenario = load_scenario("default");
  for (Flock& f : scenario.flocks) f.flocking = false;
  CpuSimulation sim(scenario);
  const testing::FlockRun run = testing::fly_flock(sim, 0, 20.0, 80.0);
  const double span = scenario.species[scenario.flocks[0].species].box_c;
  const bool spacing = run.median_nearest_low >= span && run.median_nearest_high <= 3.0 * span &&
                       run.worst_too_close < 0.005;
  const bool cohesion = run.smallest_largest_cluster >= 0.95;
  EXPECT_FALSE(spacing && cohesion);
  std::printf(
      "flocking off: median nearest %.1f-%.1f cm, worst too close %.4f, smallest largest cluster "
      "%.4f\n",
      run.median_nearest_low, run.median_nearest_high, run.worst_too_close,
      run.smallest_largest_cluster);
}

}  // namespace
}  // namespace aeroflock
