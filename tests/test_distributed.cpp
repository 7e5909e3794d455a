// One flock over MPI ranks against the same flock on one (engine/dist), on the CPU reference and on
// the Vulkan backend (a device a rank against one device): every bird's state bit for bit the same
// by global id, no bird lost or doubled at any frame, each rank's ghosts exactly the birds within
// its halo. Run under mpiexec with 1 to 4 ranks (tests/CMakeLists.txt); rank 0 flies the one-rank
// reference and reports.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dist/collectives.h"
#include "dist/distributed.h"
#include "dist/distributed_gpu.h"
#include "gpu/gpu_simulation.h"
#include "io/scenario_file.h"
#include "run/run_loop.h"

using namespace aeroflock;
using aeroflock::dist::DistributedSimulation;

namespace {

enum class Backend { cpu, vulkan };

// The flock over the ranks (each rank a device of its own on Vulkan), spawned or given.
std::unique_ptr<DistributedSimulation> many_ranks(Backend backend, const Scenario& s,
                                                  uint32_t birds) {
  if (backend == Backend::cpu)
    return std::make_unique<dist::DistributedCpuSimulation>(s, MPI_COMM_WORLD, birds);
  return std::make_unique<dist::DistributedGpuSimulation>(dist::rank_device(MPI_COMM_WORLD, -1), s,
                                                          MPI_COMM_WORLD, birds);
}
std::unique_ptr<DistributedSimulation> many_ranks(Backend backend, const Scenario& s,
                                                  const std::vector<BirdState>& birds) {
  if (backend == Backend::cpu)
    return std::make_unique<dist::DistributedCpuSimulation>(s, MPI_COMM_WORLD, birds);
  return std::make_unique<dist::DistributedGpuSimulation>(dist::rank_device(MPI_COMM_WORLD, -1), s,
                                                          MPI_COMM_WORLD, birds);
}
// The same flock on one process (and one device).
std::unique_ptr<Simulation> one_rank(Backend backend, const Scenario& s,
                                     std::vector<BirdState> birds) {
  if (backend == Backend::cpu) return std::make_unique<CpuSimulation>(s, std::move(birds));
  return std::make_unique<gpu::GpuSimulation>(
      std::make_unique<gpu::Device>(gpu::headless(-1, false)), s, std::move(birds));
}

class Distributed : public ::testing::TestWithParam<Backend> {};

int rank_here() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

// Field by field (a struct's padding is not state), exactly.
bool same_state(const BirdState& a, const BirdState& b) {
  return true
#define AF_BIRD_FIELD(gpu_type, cpp_type, name, initial) &&a.name == b.name
#include "model/bird_state.def"
#undef AF_BIRD_FIELD
      ;
}

// Every rank's birds on every rank (in no particular order).
std::vector<BirdState> all_birds(DistributedSimulation& many) {
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const std::vector<BirdState>& mine = *many.snapshot().birds;
  const int bytes = static_cast<int>(mine.size() * sizeof(BirdState));
  std::vector<int> sizes(static_cast<size_t>(ranks)), at(static_cast<size_t>(ranks));
  MPI_Allgather(&bytes, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int q = 0; q < ranks; ++q) at[size_t(q)] = total, total += sizes[size_t(q)];
  std::vector<BirdState> all(static_cast<size_t>(total) / sizeof(BirdState));
  MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), sizes.data(), at.data(), MPI_BYTE,
                 MPI_COMM_WORLD);
  return all;
}

// `values` (one per id of this rank) of every rank, ordered by id, on rank 0.
template <class T>
std::vector<T> gather_values_by_id(const std::vector<uint32_t>& ids, const std::vector<T>& values) {
  struct Row {
    uint32_t id;
    T value;
  };
  std::vector<Row> rows;
  for (size_t k = 0; k < ids.size(); ++k) rows.push_back({ids[k], values[k]});
  std::vector<Row> all = aeroflock::dist::gather_to(0, MPI_COMM_WORLD, rows);
  std::sort(all.begin(), all.end(), [](const Row& a, const Row& b) { return a.id < b.id; });
  std::vector<T> out;
  for (const Row& r : all) out.push_back(r.value);
  return out;
}

// Flies `scenario` for `frames` frames on every rank and on rank 0 alone; checks each frame that
// the ranks hold every id once, and at the end that every bird is the same.
void expect_same_as_one_rank(Backend backend, Scenario scenario, uint32_t birds, uint32_t frames,
                             bool expect_traffic = true) {
  std::unique_ptr<DistributedSimulation> many_ptr = many_ranks(backend, scenario, birds);
  DistributedSimulation& many = *many_ptr;
  const bool root = rank_here() == 0;
  uint64_t halo_ghosts = 0;  // what a halo as wide as the perception radius would have sent
  std::unique_ptr<Simulation> one;
  if (root) one = one_rank(backend, scenario, spawn_birds(scenario, birds));
  const uint64_t total = root ? one->bird_count() : 0;
  for (uint32_t f = 0; f < frames; ++f) {
    // Every bird as the frame starts, on every rank: the ghosts this rank should receive.
    const std::vector<BirdState> before = all_birds(many);
    many.step_frame();
    if (any_flocking(scenario)) {
      // The ghosts are every other rank's flocking birds where this rank looked past its cuts
      // (and, for the record, those a halo of the whole perception radius would hold).
      size_t expected = 0, in_halo = 0;
      std::vector<int> to;
      for (const BirdState& b : before) {
        if (!flocks_now(b)) continue;
        const int64_t c = many.slabs().cell_of(b.position);
        if (many.slabs().owner(c) == rank_here()) continue;
        expected += many.reach().holds(b.position[many.slabs().axis]);
        to.clear();
        many.slabs().ghost_ranks(c, to);
        in_halo += std::count(to.begin(), to.end(), rank_here());
      }
      ASSERT_EQ(many.ghost_count(), expected) << "rank " << rank_here() << " frame " << f;
      halo_ghosts += in_halo;
    }
    if (root) one->step_frame();
    // Conservation: every id exactly once over the ranks.
    std::vector<uint32_t> every = aeroflock::dist::gather_to(0, MPI_COMM_WORLD, many.ids());
    if (root) {
      std::sort(every.begin(), every.end());
      ASSERT_EQ(every.size(), total) << "frame " << f;
      for (uint32_t k = 0; k < every.size(); ++k) ASSERT_EQ(every[k], k) << "frame " << f;
    }
  }
  const std::vector<BirdState> gathered = many.gather();
  // The neighbour sets of the last tick, by their keys (sums of global ids).
  std::vector<uint32_t> keys;
  if (const std::vector<Perception>* p = many.snapshot().perception)
    for (const Perception& q : *p) keys.push_back(q.seen_key);
  const std::vector<uint32_t> all_keys = gather_values_by_id(many.ids(), keys);
  // What crossed between ranks: on several ranks a test that never migrated or ghosted a bird
  // would prove nothing.
  const uint64_t mine[4] = {many.traffic().migrants_sent, many.traffic().ghosts_sent,
                            many.traffic().rebalances, halo_ghosts};
  uint64_t sum[4] = {0, 0, 0, 0};
  MPI_Reduce(mine, sum, 4, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  if (!root) return;
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::printf(
      "%d ranks: %lu migrants, %lu ghosts sent (a whole-radius halo: %lu), %lu rebalances\n", ranks,
      (unsigned long)sum[0], (unsigned long)sum[1], (unsigned long)sum[3], (unsigned long)sum[2]);
  if (ranks > 1 && expect_traffic) {
    EXPECT_GT(sum[0], 0u) << "no bird changed rank";
    EXPECT_GT(sum[1], 0u) << "no ghost was sent";
  }
  ASSERT_EQ(gathered.size(), one->bird_count());
  size_t differ = 0;
  for (size_t i = 0; i < gathered.size(); ++i)
    if (!same_state(gathered[i], one->birds()[i])) {
      if (differ++ < 5)
        ADD_FAILURE() << "bird " << i << " differs: at " << gathered[i].position.x << ", "
                      << gathered[i].position.y << ", " << gathered[i].position.z << " against "
                      << one->birds()[i].position.x << ", " << one->birds()[i].position.y << ", "
                      << one->birds()[i].position.z;
    }
  EXPECT_EQ(differ, 0u);
  if (const std::vector<Perception>* p = one->snapshot().perception) {
    ASSERT_EQ(all_keys.size(), p->size());
    size_t unlike = 0;
    for (size_t i = 0; i < p->size(); ++i) unlike += all_keys[i] != (*p)[i].seen_key;
    EXPECT_EQ(unlike, 0u) << "birds whose neighbours differ";
  }
}

}  // namespace

TEST_P(Distributed, TheDefaultFlockIsTheSameBirdForBird) {
  Scenario s = load_scenario("default");
  expect_same_as_one_rank(GetParam(), s, 300, 100);
}

// The whole default scenario, 1,020 birds for 20 s (the full tier).
TEST_P(Distributed, TheDefaultScenarioTwentySeconds) {
  Scenario s = load_scenario("default");
  expect_same_as_one_rank(GetParam(), s, 0,
                          static_cast<uint32_t>(std::lround(s.duration / s.frame_seconds())));
}

bool same_forces(const StepForces& a, const StepForces& b) {
  return a.total == b.total && a.tail == b.tail && a.wing[0] == b.wing[0] &&
         a.wing[1] == b.wing[1] && a.wing[2] == b.wing[2] && a.wing[3] == b.wing[3] &&
         a.torque == b.torque;
}

// What an export reads: the start (perceived among the ghosts) and a frame stepped with its
// forces, the same as one rank's.
TEST_P(Distributed, TheStartAndTheRecordedForcesAreOneRanks) {
  const Scenario s = load_scenario("default");
  std::unique_ptr<DistributedSimulation> many_ptr = many_ranks(GetParam(), s, 300);
  DistributedSimulation& many = *many_ptr;
  std::unique_ptr<Simulation> one;
  if (rank_here() == 0) one = one_rank(GetParam(), s, spawn_birds(s, 300));
  many.prepare_forces();
  if (one) one->prepare_forces();
  auto compare = [&](const Snapshot& m, const char* when) {
    ASSERT_NE(m.forces, nullptr) << when;
    ASSERT_NE(m.ids, nullptr) << when;
    const std::vector<StepForces> forces = gather_values_by_id(*m.ids, *m.forces);
    std::vector<uint32_t> keys;
    for (const Perception& p : *m.perception) keys.push_back(p.seen_key);
    const std::vector<uint32_t> all_keys = gather_values_by_id(*m.ids, keys);
    if (!one) return;
    const Snapshot o = std::string(when) == "start" ? one->start_snapshot() : one->snapshot();
    ASSERT_EQ(forces.size(), o.forces->size()) << when;
    for (size_t i = 0; i < forces.size(); ++i) {
      EXPECT_TRUE(same_forces(forces[i], (*o.forces)[i])) << when << ": bird " << i;
      EXPECT_EQ(all_keys[i], (*o.perception)[i].seen_key) << when << ": bird " << i;
    }
  };
  compare(many.start_snapshot(), "start");
  for (int f = 0; f < 29; ++f) {
    many.step_frame();
    if (one) one->step_frame();
  }
  many.step_frame(true);
  if (one) one->step_frame(true);
  compare(many.snapshot(), "frame 30");
}

// Issue 43: flocks that meet each other's wakes, the ghosts carrying what a wake follows from
// (attitude, lift, wingbeat): the default flock with wakes, and the ibises' formation flying.
TEST_P(Distributed, AFlockThatMeetsTheWakesIsTheSameBirdForBird) {
  Scenario s = load_scenario("default");
  for (Flock& f : s.flocks) f.wake = f.flocking;
  ASSERT_TRUE(any_wake(s));
  expect_same_as_one_rank(GetParam(), s, 300, 100);
}

TEST_P(Distributed, TheIbisesFormationIsTheSameBirdForBird) {
  const Scenario s = load_scenario("ibis-v");
  ASSERT_TRUE(any_wake(s));
  expect_same_as_one_rank(GetParam(), s, 0, 300, false);
}

// The migrating flock flies its route through several slabs with its turns; the cuts follow it.
TEST_P(Distributed, TheMigratingFlockThroughItsSlabs) {
  Scenario s = load_scenario("migration-flock");
  expect_same_as_one_rank(GetParam(), s, 400, 600);
}

// Two flocks 3 km apart along the cut axis: ranks between them hold no bird.
TEST_P(Distributed, TwoFlocksFarApart) {
  Scenario s = load_scenario("default");
  Flock far = s.flocks.front();
  far.spawn_centre.x += 300000.0;
  s.flocks.push_back(far);
  expect_same_as_one_rank(GetParam(), s, 400, 100,
                          false);  // on 2 ranks each flock alone on its own
}

// Every bird exactly on a cell's face, so some exactly on a cut (cuts fall on faces): owned by the
// slab after it, perceived by both sides' ghosts as on one rank.
TEST_P(Distributed, BirdsExactlyOnTheCuts) {
  const Scenario s = load_scenario("default");
  std::vector<BirdState> birds = spawn_birds(s, 300);
  const double cell = grid_shape(s.species, birds).cell;
  for (BirdState& b : birds) {
    b.position.x = std::round(b.position.x / cell) * cell;
    b.position.z = std::round(b.position.z / cell) * cell;
  }
  std::unique_ptr<DistributedSimulation> many_ptr = many_ranks(GetParam(), s, birds);
  DistributedSimulation& many = *many_ptr;
  for (size_t k = 0; k < many.ids().size(); ++k) {
    const int64_t c = many.slabs().cell_of(many.snapshot().birds->at(k).position);
    EXPECT_EQ(many.slabs().owner(c), many.rank());
  }
  std::unique_ptr<Simulation> one;
  if (rank_here() == 0) one = one_rank(GetParam(), s, birds);
  for (int f = 0; f < 30; ++f) {
    many.step_frame();
    if (one) one->step_frame();
  }
  const std::vector<BirdState> gathered = many.gather();
  if (!one) return;
  ASSERT_EQ(gathered.size(), birds.size());
  for (size_t i = 0; i < gathered.size(); ++i)
    EXPECT_TRUE(same_state(gathered[i], one->birds()[i])) << "bird " << i;
}

// A flocking species that sees no neighbour (neighbours = 0): no ghosts asked for, the same run.
TEST_P(Distributed, ASpeciesThatSeesNoNeighbour) {
  Scenario s = load_scenario("default");
  for (Species& sp : s.species) sp.neighbours = 0;
  expect_same_as_one_rank(GetParam(), s, 200, 30, false);
}

TEST_P(Distributed, MoreRanksThanBirds) {
  Scenario s = load_scenario("default");
  expect_same_as_one_rank(GetParam(), s, 2, 20, false);
}

// A rank's device share made with room for half again its birds and no more (at least 1): the
// ghosts and migrants make it grow mid-run, each time made again larger, its clock continued; the
// run stays one device's, bird for bird.
TEST(DistributedVulkan, ASmallShareGrowsAndStaysOneDevices) {
  const Scenario s = load_scenario("default");
  dist::DistributedGpuSimulation many(dist::rank_device(MPI_COMM_WORLD, -1), s, MPI_COMM_WORLD, 300,
                                      1);
  std::unique_ptr<Simulation> one;
  if (rank_here() == 0) one = one_rank(Backend::vulkan, s, spawn_birds(s, 300));
  for (int f = 0; f < 60; ++f) {
    many.step_frame();
    if (one) one->step_frame();
  }
  const std::vector<BirdState> gathered = many.gather();
  uint64_t mine = many.growths(), growths = 0;
  MPI_Reduce(&mine, &growths, 1, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
  if (!one) return;
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::printf("%d ranks: the shares grew %lu times\n", ranks, (unsigned long)growths);
  if (ranks > 1) {
    EXPECT_GT(growths, 0u) << "no share grew";
  }
  ASSERT_EQ(gathered.size(), one->bird_count());
  for (size_t i = 0; i < gathered.size(); ++i)
    EXPECT_TRUE(same_state(gathered[i], one->birds()[i])) << "bird " << i;
}

// A rank whose step throws after the frame's exchanges (a device error, say) skips the frame's
// observers, and so must every rank: their calls may be collective (here a barrier, as the VTK
// pieces' count and the gathering for pictures are). Before Simulation::stepped_together the
// others waited in the observer for the failed rank: a hang. Every rank then stops on the next
// frame, the failed one with its error, the others for another rank's error.
TEST(DistributedRun, AStepThatFailsOnOneRankStopsEveryRankWithoutAHang) {
  const Scenario s = load_scenario("default");
  dist::DistributedCpuSimulation flock(s, MPI_COMM_WORLD, 200);
  int ranks = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const int failing = ranks - 1;
  constexpr uint64_t kFailingFrame = 3;
  // The flock, its step failing on the last rank after frame kFailingFrame's work.
  struct FailingStep final : Simulation {
    DistributedSimulation& inner;
    bool fails;
    FailingStep(DistributedSimulation& d, bool f) : Simulation(d.scenario()), inner(d), fails(f) {}
    std::string backend() const override { return inner.backend(); }
    std::string device() const override { return inner.device(); }
    size_t bird_count() const override { return inner.bird_count(); }
    void step(uint32_t steps, bool forces) override {
      inner.step(steps, forces);
      if (fails && inner.frames() == kFailingFrame) throw std::runtime_error("the device failed");
    }
    Snapshot snapshot() override { return inner.snapshot(); }
    int stops_together(int here) override { return inner.stops_together(here); }
    bool stepped_together(bool here) override { return inner.stepped_together(here); }
  } sim(flock, flock.rank() == failing);
  struct Collective final : RunObserver {
    uint64_t seen = 0;
    void frame(Simulation&, uint64_t) override {
      MPI_Barrier(MPI_COMM_WORLD);
      ++seen;
    }
  } collective;
  RunLimits limits;
  limits.frames = 10;
  const RunResult result = run_frames(sim, {&collective}, limits);
  EXPECT_EQ(collective.seen, kFailingFrame - 1) << "rank " << flock.rank();
  if (flock.rank() == failing) {
    EXPECT_EQ(result.end, RunResult::End::error);
    ASSERT_EQ(result.errors.size(), 1u);
    EXPECT_EQ(result.errors[0], "the device failed");
  } else {
    EXPECT_EQ(result.end, RunResult::End::observer) << "rank " << flock.rank();
    EXPECT_EQ(result.stopped_by, "another rank's error") << "rank " << flock.rank();
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, Distributed, ::testing::Values(Backend::cpu, Backend::vulkan),
                         [](const auto& info) {
                           return info.param == Backend::cpu ? "cpu" : "vulkan";
                         });

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only rank 0 reports; every rank runs every test (they are collective).
  if (rank_here() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int failed = RUN_ALL_TESTS();
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any;
}
