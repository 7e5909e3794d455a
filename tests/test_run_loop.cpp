// The run loop (engine/run/run_loop.h) in-process, on the CPU reference: each observer's hooks in
// order, every way a run ends (its frames, an observer, a signal, an error), batching, forces on
// the frames asked, and --strict.
#include <gtest/gtest.h>

#include <csignal>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/scenario_file.h"
#include "run/run_loop.h"

namespace aeroflock {
namespace {

// Writes down what it was called with; optionally stops, signals, throws, or asks for forces.
struct Recorder : RunObserver {
  std::vector<std::string> calls;
  std::vector<uint64_t> frames_seen, sim_frames;
  bool every_frame = true;
  uint64_t stop_at = 0, throw_at = 0, signal_at = 0, forces_at = 0;
  bool throw_in_finish = false;
  volatile std::sig_atomic_t* signal = nullptr;
  std::vector<bool> had_forces;

  void start(Simulation& sim) override { calls.push_back("start t=" + std::to_string(sim.time())); }
  bool wants_forces(uint64_t frame, bool last) const override {
    return frame == forces_at || (forces_at && last);
  }
  bool reads_every_frame() const override { return every_frame; }
  void frame(Simulation& sim, uint64_t frames) override {
    calls.push_back("frame");
    frames_seen.push_back(frames);
    sim_frames.push_back(sim.frames());
    if (forces_at) had_forces.push_back(sim.snapshot().forces != nullptr);
    if (frames == throw_at) throw std::runtime_error("cannot write x.png: No space left on device");
    if (frames == signal_at && signal) *signal = SIGTERM;
  }
  std::string stop_reason() const override {
    return stop_at && !frames_seen.empty() && frames_seen.back() >= stop_at ? "judged" : "";
  }
  void finish(Simulation& sim) override {
    calls.push_back("finish frames=" + std::to_string(sim.frames()));
    if (throw_in_finish) throw std::runtime_error("cannot write s.json: No space left on device");
  }
};

std::unique_ptr<Simulation> small_sim() {
  return std::make_unique<CpuSimulation>(load_scenario("fig17-ground-effect"));
}

TEST(RunLoop, EachObserverStartsSeesEveryFrameAndFinishesInOrder) {
  auto sim = small_sim();
  Recorder a, b;
  const RunResult r = run_frames(*sim, {&a, &b}, {.frames = 5});
  EXPECT_EQ(r.end, RunResult::End::flown);
  EXPECT_EQ(r.frames, 5u);
  EXPECT_TRUE(r.errors.empty());
  EXPECT_EQ(sim->frames(), 5u);
  for (const Recorder* o : {&a, &b}) {
    ASSERT_EQ(o->calls.size(), 7u);
    EXPECT_EQ(o->calls.front(), "start t=0.000000");
    EXPECT_EQ(o->calls.back(), "finish frames=5");
    EXPECT_EQ(o->frames_seen, (std::vector<uint64_t>{1, 2, 3, 4, 5}));
    EXPECT_EQ(o->sim_frames, o->frames_seen);
  }
}

TEST(RunLoop, AnObserverStopsItAndEveryObserverStillFinishes) {
  auto sim = small_sim();
  Recorder judge, other;
  judge.stop_at = 3;
  const RunResult r = run_frames(*sim, {&judge, &other}, {.frames = 100});
  EXPECT_EQ(r.end, RunResult::End::observer);
  EXPECT_EQ(r.stopped_by, "judged");
  EXPECT_EQ(r.frames, 3u);
  EXPECT_EQ(other.calls.back(), "finish frames=3");
}

TEST(RunLoop, ASignalStopsItAfterTheFrame) {
  auto sim = small_sim();
  volatile std::sig_atomic_t signal = 0;
  Recorder o;
  o.signal = &signal;
  o.signal_at = 4;
  const RunResult r = run_frames(*sim, {&o}, {.frames = 100, .signal = &signal});
  EXPECT_EQ(r.end, RunResult::End::signal);
  EXPECT_EQ(r.signal, SIGTERM);
  EXPECT_EQ(r.frames, 4u);
  EXPECT_EQ(o.calls.back(), "finish frames=4");
  // A signal during the last frame: every frame flown, and the run still counts as interrupted.
  signal = 0;
  auto again = small_sim();
  Recorder last;
  last.signal = &signal;
  last.signal_at = 2;
  EXPECT_EQ(run_frames(*again, {&last}, {.frames = 2, .signal = &signal}).end,
            RunResult::End::signal);
}

TEST(RunLoop, AnErrorStopsItAndErrorsComeInOrder) {
  auto sim = small_sim();
  Recorder pictures, summary;
  pictures.throw_at = 2;
  summary.throw_in_finish = true;
  const RunResult r = run_frames(*sim, {&pictures, &summary}, {.frames = 10});
  EXPECT_EQ(r.end, RunResult::End::error);
  EXPECT_EQ(r.frames, 2u);
  EXPECT_EQ(r.errors, (std::vector<std::string>{"cannot write x.png: No space left on device",
                                                "cannot write s.json: No space left on device"}));
  // The observer after the one that threw still saw that frame (over many ranks its call may be
  // collective), and finished.
  EXPECT_EQ(summary.frames_seen, (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(summary.calls.back(), "finish frames=2");
}

// A simulation flown by several processes (dist/) stops where any of them must: here, another
// "rank" asks to stop after frame `others_stop_at`, and this one's own reasons are recorded.
class OneOfSeveral final : public Simulation {
 public:
  explicit OneOfSeveral(uint64_t others_stop_at)
      : Simulation(load_scenario("fig17-ground-effect")), cpu_(scenario()), at_(others_stop_at) {}
  std::string backend() const override { return "cpu"; }
  std::string device() const override { return "test"; }
  size_t bird_count() const override { return cpu_.bird_count(); }
  void step(uint32_t steps, bool forces) override {
    begin_frame();
    cpu_.step(steps, forces);
    end_frame(steps);
  }
  Snapshot snapshot() override { return cpu_.snapshot(); }
  int stops_together(int here) override {
    asked.push_back(here);
    return frames() >= at_ ? std::max(here, why_) : here;
  }
  std::vector<int> asked;
  int why_ = 1;  // the other rank's reason, in the run loop's codes

 private:
  CpuSimulation cpu_;
  uint64_t at_;
};

TEST(RunLoop, EveryPartStopsOnTheFrameAnyMust) {
  {
    OneOfSeveral sim(3);
    Recorder o;
    const RunResult r = run_frames(sim, {&o}, {.frames = 100});
    EXPECT_EQ(r.end, RunResult::End::observer);
    EXPECT_EQ(r.stopped_by, "another rank");
    EXPECT_EQ(r.frames, 3u);
    EXPECT_EQ(sim.asked, (std::vector<int>{0, 0, 0, 0}));
  }
  {
    // Another rank caught SIGTERM: this one stops as interrupted by it.
    OneOfSeveral sim(2);
    sim.why_ = 256 + SIGTERM;
    Recorder o;
    const RunResult r = run_frames(sim, {&o}, {.frames = 100});
    EXPECT_EQ(r.end, RunResult::End::signal);
    EXPECT_EQ(r.signal, SIGTERM);
    EXPECT_EQ(r.frames, 2u);
  }
  {
    // Its own error: it asks the others to stop at the frame's end, and stops.
    OneOfSeveral sim(100);
    Recorder o;
    o.throw_at = 2;
    const RunResult r = run_frames(sim, {&o}, {.frames = 100});
    EXPECT_EQ(r.end, RunResult::End::error);
    EXPECT_EQ(r.frames, 2u);
    EXPECT_EQ(sim.asked, (std::vector<int>{0, 0, 2}));
  }
}

TEST(RunLoop, FramesGoSeveralToASubmissionOnlyWhenNoObserverReadsEach) {
  {
    auto sim = small_sim();
    Recorder o;
    o.every_frame = false;
    const RunResult r = run_frames(*sim, {&o}, {.frames = 10, .batch = 4});
    EXPECT_EQ(r.frames, 10u);
    EXPECT_EQ(o.frames_seen, (std::vector<uint64_t>{4, 8, 10}));
    EXPECT_EQ(sim->frames(), 10u);
  }
  {
    auto sim = small_sim();
    Recorder batched, each;
    batched.every_frame = false;
    run_frames(*sim, {&batched, &each}, {.frames = 10, .batch = 4});
    EXPECT_EQ(each.frames_seen.size(), 10u);
  }
}

TEST(RunLoop, TheFramesAnObserverAsksForCarryForces) {
  auto sim = small_sim();
  Recorder o;
  o.forces_at = 3;
  run_frames(*sim, {&o}, {.frames = 6});
  EXPECT_EQ(o.had_forces,
            (std::vector<bool>{false, false, true, false, false, true}));  // 3 and the last
}

TEST(RunLoop, StrictStopsAtTheFirstQuarantinedBirdAndSaysWhich) {
  Scenario s = load_scenario(AEROFLOCK_TEST_DATA "/nan_quarantine.toml");
  make_flock_non_finite(s, "doomed");
  CpuSimulation sim(s);
  StrictCheck strict;
  const RunResult r = run_frames(sim, {&strict}, {.frames = 1000});
  EXPECT_EQ(r.end, RunResult::End::observer);
  EXPECT_EQ(r.stopped_by, "--strict");
  EXPECT_LT(r.frames, 1000u);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_TRUE(r.errors[0].starts_with("--strict: bird ")) << r.errors[0];
  EXPECT_NE(r.errors[0].find("state became non-finite at t = "), std::string::npos) << r.errors[0];

  // Without a quarantined bird it says nothing.
  auto clean = small_sim();
  StrictCheck quiet;
  const RunResult ok = run_frames(*clean, {&quiet}, {.frames = 3});
  EXPECT_EQ(ok.end, RunResult::End::flown);
  EXPECT_TRUE(ok.errors.empty());
}

// The viewer's pace: an observer sets each turn's steps (none while paused, a frame and a half
// at speed x1.5), the run counts turns, and the simulation flies exactly the steps asked.
struct Pacer : RunObserver {
  std::vector<uint32_t> steps;  // one per turn
  size_t turn = 0;
  std::vector<double> times;
  std::optional<uint32_t> pace(Simulation&) override { return steps[turn++]; }
  void frame(Simulation& sim, uint64_t) override { times.push_back(sim.time()); }
};

TEST(RunLoop, AnObserverPacesItsTurnsStepByStep) {
  auto sim = small_sim();
  const uint32_t frame = sim->scenario().steps_per_frame;
  Pacer pacer;
  pacer.steps = {0, frame + frame / 2, 0, 3};
  Recorder other;  // sees each turn, whatever its steps
  const RunResult r = run_frames(*sim, {&pacer, &other}, {.frames = 4});
  EXPECT_EQ(r.frames, 4u);
  EXPECT_EQ(other.frames_seen, (std::vector<uint64_t>{1, 2, 3, 4}));
  const double dt = sim->scenario().dt;
  ASSERT_EQ(pacer.times.size(), 4u);
  EXPECT_EQ(pacer.times[0], 0.0);  // paused: not a step
  EXPECT_NEAR(pacer.times[1], (frame + frame / 2) * dt, 1e-12);
  EXPECT_EQ(pacer.times[2], pacer.times[1]);
  EXPECT_NEAR(pacer.times[3], (frame + frame / 2 + 3) * dt, 1e-12);

  // The same steps in one go fly the same birds, bit for bit.
  auto once = small_sim();
  once->step(frame + frame / 2 + 3);
  EXPECT_EQ(once->birds()[0].position, sim->birds()[0].position);
}

// FrameTimes: one wall time a frame, each frame's birds read back, none negative.
TEST(RunLoop, FrameTimesTimesEachFrame) {
  auto sim = small_sim();
  FrameTimes times;
  run_frames(*sim, {&times}, {.frames = 4, .batch = 4});
  ASSERT_EQ(times.milliseconds().size(), 4u);  // it reads every frame: no batching
  for (double ms : times.milliseconds()) EXPECT_GE(ms, 0.0);
}

// Simulation::retire on the CPU reference: a retired bird is no longer stepped (its state stays),
// and the others fly exactly as they would have (the envelope's judged birds).
TEST(Retire, ARetiredBirdStaysWhereItWasAndTheOthersFlyAsBefore) {
  const Scenario s = load_scenario(AEROFLOCK_TEST_DATA "/nan_quarantine.toml");
  CpuSimulation all(s), some(s);
  ASSERT_EQ(all.bird_count(), 2u);
  for (int f = 0; f < 2; ++f) all.step_frame(), some.step_frame();
  const BirdState at_retirement = some.birds()[1];
  some.retire(std::vector<uint32_t>{1});
  for (int f = 0; f < 5; ++f) all.step_frame(), some.step_frame();
  EXPECT_EQ(some.birds()[1].position, at_retirement.position);
  EXPECT_EQ(some.birds()[1].velocity, at_retirement.velocity);
  EXPECT_NE(all.birds()[1].position, at_retirement.position);
  EXPECT_EQ(some.birds()[0].position, all.birds()[0].position);  // bit for bit
  EXPECT_EQ(some.birds()[0].attitude, all.birds()[0].attitude);
  EXPECT_EQ(some.time(), all.time());
}

// The frames a run needs to reach a time, counted as Simulation::time() counts it.
TEST(Scenario, FramesReachingCountsTimeAsTheSimulationDoes) {
  Scenario s = load_scenario("fig17-ground-effect");
  EXPECT_EQ(s.frames_reaching(0.0), 0u);
  EXPECT_EQ(s.frames_reaching(-1.0), 0u);
  EXPECT_EQ(s.frames_reaching(s.frame_seconds() * 0.5), 1u);
  for (double t = 0.001; t < 20.0; t *= 1.37) {
    uint64_t k = 0;  // the first whole frame whose time is at least t, one by one
    while (double(k * s.steps_per_frame) * s.dt < t) ++k;
    EXPECT_EQ(s.frames_reaching(t), k) << t;
    EXPECT_GE(double(k * s.steps_per_frame) * s.dt, t);
  }
}

}  // namespace
}  // namespace aeroflock
