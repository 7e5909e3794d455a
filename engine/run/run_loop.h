// The run loop: one loop that advances any Simulation frame by frame (or at the pace an observer
// sets: the window's speed) and hands each frame to its observers (the VTK export, the pictures,
// the progress line, the --strict check, the judges of a flight), until the run's frames are flown
// or something stops it: a signal, an observer (a writer that failed, --strict, every flight
// judged) or an error. Every command flies through it; what a command adds is observers.
// HOOMD-blue's writers on triggers and FLAME GPU 2's simulate() have this shape.
//
//   RunLimits limits{.frames = 100};
//   StrictCheck strict;                 // an observer of one's own, written once
//   RunResult r = run_frames(sim, {&progress, &strict, &vtk}, limits);
//   for (const std::string& e : r.errors) ...
#pragma once

#include <chrono>
#include <csignal>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "model/simulation.h"

namespace aeroflock {

// What watches a run. Each hook is called for every observer in the order given to run_frames.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  // Before the first frame, at t = 0.
  virtual void start(Simulation&) {}
  // Whether the frame about to be stepped, number `frame` (Simulation::frames() after it; from
  // 1), must record its forces; `last` when it is the run's last.
  virtual bool wants_forces(uint64_t frame, bool last) const {
    (void)frame, (void)last;
    return false;
  }
  // The steps the next turn takes, where this observer sets the run's pace (the viewer: its
  // speed, 0 while paused); nullopt: a scenario frame's. Called before each turn; the first
  // observer that answers paces the run, and the run then counts turns, not frames.
  virtual std::optional<uint32_t> pace(Simulation&) { return std::nullopt; }
  // Whether it looks at every frame. Where none does, frames are stepped several to a submission
  // (Simulation::step_frames) and the observers see only each batch's last.
  virtual bool reads_every_frame() const { return true; }
  // After each frame (or batch): `frames` flown so far. Throws std::runtime_error to stop the
  // run with an error (a picture that could not be written).
  virtual void frame(Simulation&, uint64_t frames) { (void)frames; }
  // Why the run should stop now (an observer's reason, "" to go on): checked after each frame.
  virtual std::string stop_reason() const { return {}; }
  // After the last frame, whatever ended the run, and after the device has finished it: closes
  // the observer's outputs. Throws std::runtime_error when that fails (the run's error then).
  virtual void finish(Simulation&) {}
};

struct RunLimits {
  uint64_t frames = 0;  // flown at most
  // Set by a signal handler (its number): the run stops after the frame in progress.
  const volatile std::sig_atomic_t* signal = nullptr;
  // Frames a submission may carry when no observer reads every frame (1: one at a time).
  uint64_t batch = 1;
};

struct RunResult {
  enum class End { flown, signal, observer, error };
  End end = End::flown;
  uint64_t frames = 0;              // flown
  int signal = 0;                   // the signal that stopped it (End::signal)
  std::string stopped_by;           // the observer's reason (End::observer)
  std::vector<std::string> errors;  // every error, in the order they came: the first is the run's
  double wall_seconds = 0.0;        // the frames, the device's work waited for
};

// Flies `sim` through its observers: start, then each frame (stepped with its forces when one
// asks), then finish for each. Errors thrown by an observer's start() or frame() stop the run
// after that frame (the other observers still see it: over many ranks their calls may be
// collective); by its finish(), are collected; either way every observer is finished.
RunResult run_frames(Simulation& sim, std::span<RunObserver* const> observers,
                     const RunLimits& limits);
inline RunResult run_frames(Simulation& sim, std::initializer_list<RunObserver*> observers,
                            const RunLimits& limits) {
  return run_frames(sim, std::span<RunObserver* const>(observers.begin(), observers.size()),
                    limits);
}

// --strict: stops the run at the first bird quarantined (its state became non-finite), and
// finish() throws "--strict: bird B's state became non-finite at t = T s; stopped at t = S s".
class StrictCheck final : public RunObserver {
 public:
  bool reads_every_frame() const override { return false; }  // a batch's last frame will do
  void frame(Simulation& sim, uint64_t frames) override;
  std::string stop_reason() const override { return quarantined_ ? "--strict" : ""; }
  void finish(Simulation& sim) override;

 private:
  bool quarantined_ = false;
};

// Each frame's wall time in ms, from the end of the one before (or the run's start) until this
// one is complete and its birds read back, as someone who looks at every frame would wait: the
// benchmark's measure. Put it last, so that a frame's time holds the other observers' work.
class FrameTimes final : public RunObserver {
 public:
  void start(Simulation&) override;
  void frame(Simulation& sim, uint64_t frames) override;
  const std::vector<double>& milliseconds() const { return ms_; }

 private:
  std::chrono::steady_clock::time_point mark_;
  std::vector<double> ms_;
};

}  // namespace aeroflock
