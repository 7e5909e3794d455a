// The slab decomposition's arithmetic (engine/dist/slabs.h): owners, ghosts' ranks and cuts from
// counts per cell, against counts done by hand and by brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "dist/slabs.h"

using namespace aeroflock::dist;

namespace {
Slabs slabs(std::vector<int64_t> cuts, int64_t halo) {
  Slabs s;
  s.cell = 100.0;
  s.halo = halo;
  s.cuts = std::move(cuts);
  return s;
}
uint64_t birds_of(const CellCounts& counts, const Slabs& s, int rank) {
  uint64_t n = 0;
  for (const auto& [c, k] : counts)
    if (s.owner(c) == rank) n += k;
  return n;
}
}  // namespace

TEST(Slabs, AnOwnerFollowsFromTheCellAlone) {
  const Slabs s = slabs({0, 10, 10, 25}, 3);
  EXPECT_EQ(s.ranks(), 5);
  EXPECT_EQ(s.owner(-1000000), 0);
  EXPECT_EQ(s.owner(-1), 0);
  EXPECT_EQ(s.owner(0), 1);  // a cut's own cell belongs to the slab after it
  EXPECT_EQ(s.owner(9), 1);
  EXPECT_EQ(s.owner(10), 3);  // rank 2 owns [10, 10): nothing
  EXPECT_TRUE(s.empty(2));
  EXPECT_EQ(s.owner(24), 3);
  EXPECT_EQ(s.owner(25), 4);
  EXPECT_EQ(s.cell_of({-0.5, 0.0, 0.0}), -1);  // floor, not truncation
  EXPECT_EQ(s.cell_of({199.99, 0.0, 0.0}), 1);
}

TEST(Slabs, GhostsGoToEveryOtherRankWithinTheHalo) {
  const Slabs s = slabs({0, 10, 10, 25}, 3);
  // By brute force: the ranks, not the owner and not empty, owning a cell of [c - 3, c + 3].
  for (int64_t c = -10; c <= 35; ++c) {
    std::vector<int> want, got;
    for (int64_t d = c - 3; d <= c + 3; ++d)
      if (s.owner(d) != s.owner(c)) want.push_back(s.owner(d));
    std::sort(want.begin(), want.end());
    want.erase(std::unique(want.begin(), want.end()), want.end());
    s.ghost_ranks(c, got);
    EXPECT_EQ(got, want) << "cell " << c;
  }
}

TEST(Slabs, BalancedCutsShareTheBirdsOutAndKeepSlabsAHaloWide) {
  std::mt19937 rng(7);
  std::normal_distribution<double> spread(0.0, 40.0);
  std::vector<int64_t> cells;
  for (int i = 0; i < 10000; ++i) cells.push_back(static_cast<int64_t>(std::floor(spread(rng))));
  std::sort(cells.begin(), cells.end());
  CellCounts counts;
  for (int64_t c : cells)
    if (!counts.empty() && counts.back().first == c)
      ++counts.back().second;
    else
      counts.emplace_back(c, 1);
  for (int ranks : {1, 2, 3, 4, 7}) {
    const Slabs s = slabs(balanced_cuts(counts, ranks, 5), 5);
    uint64_t most = 0, total = 0;
    for (int r = 0; r < ranks; ++r) {
      most = std::max(most, birds_of(counts, s, r));
      total += birds_of(counts, s, r);
    }
    EXPECT_EQ(total, 10000u);
    // Within a cell's birds (about 100 at the peak) of the mean.
    EXPECT_LE(double(most), 10000.0 / ranks + 110.0) << ranks << " ranks";
    for (size_t k = 1; k < s.cuts.size(); ++k) EXPECT_GE(s.cuts[k] - s.cuts[k - 1], 5);
  }
}

TEST(Slabs, AFlockShorterThanTheRanksLeavesTheLastRanksEmpty) {
  // 12 cells of birds, halo 5: two slabs at most.
  CellCounts counts;
  for (int64_t c = 100; c < 112; ++c) counts.emplace_back(c, 10);
  const Slabs s = slabs(balanced_cuts(counts, 4, 5), 5);
  EXPECT_EQ(birds_of(counts, s, 0) + birds_of(counts, s, 1), 120u);
  EXPECT_EQ(birds_of(counts, s, 0), 50u);  // cells 100-104: a halo wide, though 3 would balance
  EXPECT_EQ(birds_of(counts, s, 2) + birds_of(counts, s, 3), 0u);
  // One bird, four ranks.
  const Slabs one = slabs(balanced_cuts({{3, 1}}, 4, 5), 5);
  int owners = 0;
  for (int r = 0; r < 4; ++r) owners += birds_of({{3, 1}}, one, r) == 1;
  EXPECT_EQ(owners, 1);
}

TEST(Slabs, ARebalanceMovesEachCutABoundedWay) {
  CellCounts counts;
  for (int64_t c = 0; c < 1000; ++c) counts.emplace_back(c, 1);
  const std::vector<int64_t> now{10, 20, 30};
  const std::vector<int64_t> next = rebalanced_cuts(now, counts, 5, 40);
  ASSERT_EQ(next.size(), 3u);
  for (size_t k = 0; k < 3; ++k) EXPECT_LE(std::abs(next[k] - now[k]), 40) << k;
  EXPECT_EQ(next, (std::vector<int64_t>{50, 60, 70}));
  // Repeated, they reach the balanced cuts.
  std::vector<int64_t> cuts = now;
  for (int k = 0; k < 30; ++k) cuts = rebalanced_cuts(cuts, counts, 5, 40);
  EXPECT_EQ(cuts, balanced_cuts(counts, 4, 5));
  EXPECT_TRUE(imbalanced(std::vector<uint64_t>{106, 100, 94, 100}, 1.05));
  EXPECT_FALSE(imbalanced(std::vector<uint64_t>{104, 100, 96, 100}, 1.05));
}
