#include "run/run_loop.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "io/summary.h"

namespace aeroflock {

RunResult run_frames(Simulation& sim, std::span<RunObserver* const> observers,
                     const RunLimits& limits) {
  RunResult result;
  const auto start = std::chrono::steady_clock::now();
  const bool each_frame = std::any_of(observers.begin(), observers.end(),
                                      [](const RunObserver* o) { return o->reads_every_frame(); });
  const uint64_t batch = each_frame ? 1 : std::max<uint64_t>(limits.batch, 1);
  auto stop_now = [&] {
    if (limits.signal && *limits.signal) {
      result.end = RunResult::End::signal;
      result.signal = int(*limits.signal);
      return true;
    }
    for (const RunObserver* o : observers)
      if (std::string why = o->stop_reason(); !why.empty()) {
        result.end = RunResult::End::observer;
        result.stopped_by = std::move(why);
        return true;
      }
    return false;
  };

  // Each observer is called whatever the one before it threw: over many ranks an observer's call
  // may be collective (dist/), and every rank must make it.
  auto each = [&](auto&& call) {
    for (RunObserver* o : observers) try {
        call(o);
      } catch (const std::runtime_error& e) {
        result.end = RunResult::End::error;
        result.errors.push_back(e.what());
      }
  };
  each([&](RunObserver* o) { o->start(sim); });
  // Every part of the run stops on the same frame, for the strongest reason any part has
  // (Simulation::stops_together): a signal, then an error, then an observer's.
  constexpr int kByObserver = 1, kByError = 2, kBySignal = 256;  // kBySignal + its number
  while (result.frames < limits.frames) {
    const bool error = result.end == RunResult::End::error;
    const bool stop = error || stop_now();
    const int here = !stop                                  ? 0
                     : result.end == RunResult::End::signal ? kBySignal + result.signal
                     : error                                ? kByError
                                                            : kByObserver;
    if (const int why = sim.stops_together(here); why != 0) {
      if (why >= kBySignal && result.end != RunResult::End::signal) {
        result.end = RunResult::End::signal;
        result.signal = why - kBySignal;
      } else if (!stop) {
        result.end = RunResult::End::observer;
        result.stopped_by = why == kByError ? "another rank's error" : "another rank";
      }
      break;
    }
    bool stepped = false;
    try {
      std::optional<uint32_t> paced;
      for (RunObserver* o : observers)
        if (!paced) paced = o->pace(sim);
      const uint64_t n = paced ? 1 : std::min(batch, limits.frames - result.frames);
      if (n > 1) {
        sim.step_frames(uint32_t(n));
      } else {
        const uint64_t next = sim.frames() + 1;
        const bool last = result.frames + 1 == limits.frames;
        const bool forces =
            std::any_of(observers.begin(), observers.end(),
                        [&](const RunObserver* o) { return o->wants_forces(next, last); });
        const uint32_t steps = paced ? *paced : sim.scenario().steps_per_frame;
        if (steps > 0) sim.step(steps, forces);
      }
      result.frames += n;
      stepped = true;
    } catch (const std::runtime_error& e) {
      result.end = RunResult::End::error;
      result.errors.push_back(e.what());
    }
    if (sim.stepped_together(stepped)) each([&](RunObserver* o) { o->frame(sim, result.frames); });
  }
  // A signal that came during the last frame stops nothing more, but the run was interrupted.
  if (result.end == RunResult::End::flown && limits.signal && *limits.signal) {
    result.end = RunResult::End::signal;
    result.signal = int(*limits.signal);
  }
  if (result.frames > 0) sim.snapshot();  // the device has finished the last frame
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (RunObserver* o : observers) {
    try {
      o->finish(sim);
    } catch (const std::runtime_error& e) {
      result.errors.push_back(e.what());
    }
  }
  return result;
}

void StrictCheck::frame(Simulation& sim, uint64_t) {
  // The newest state ready without waiting for the device: a quarantined bird stays so.
  quarantined_ =
      quarantined_ || !quarantined_birds(*sim.ready_snapshot().birds, sim.scenario().dt, 1).empty();
}

void StrictCheck::finish(Simulation& sim) {
  const Snapshot now = sim.snapshot();
  std::vector<QuarantinedBird> first = quarantined_birds(*now.birds, sim.scenario().dt, 1);
  if (first.empty()) return;
  // One rank's share of a flock over many: its global id.
  if (now.ids) first.front().bird = (*now.ids)[first.front().bird];
  char why[160];
  std::snprintf(
      why, sizeof why,
      "--strict: bird %llu's state became non-finite at t = %.4f s; stopped at t = %.3f s",
      (unsigned long long)first.front().bird, first.front().time, sim.time());
  throw std::runtime_error(why);
}

void FrameTimes::start(Simulation&) { mark_ = std::chrono::steady_clock::now(); }

void FrameTimes::frame(Simulation& sim, uint64_t) {
  (void)sim.birds();
  const auto now = std::chrono::steady_clock::now();
  ms_.push_back(std::chrono::duration<double, std::milli>(now - mark_).count());
  mark_ = now;
}

}  // namespace aeroflock
