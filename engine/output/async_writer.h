// The outputs' writer thread: what a run hands to the disk (a VTK frame, a PNG to encode, a video
// frame for ffmpeg) is queued as a job and done in order on a thread of its own, so that the run
// waits for the disk only when the queue is full. The queue is bounded in jobs and in bytes (a
// slow disk slows the run instead of filling memory). The first job that throws stops the writer:
// the jobs after it are dropped, failed() says so at once and finish() rethrows it.
//
//   AsyncWriter writer({.jobs = 4, .bytes = 256 << 20});
//   writer.push(pixels.size(), [pixels = std::move(pixels)] { write_png(...); });
//   writer.finish();  // waits for every job; throws the first error
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace aeroflock {

class AsyncWriter {
 public:
  struct Limits {
    size_t jobs = 4;                   // waiting besides the one being done (at least 1)
    size_t bytes = size_t(256) << 20;  // their bytes (an empty queue takes any job)
  };
  struct Use {  // the most that waited at once
    size_t jobs = 0;
    size_t bytes = 0;
  };
  // `idle`, when given, is called on the writer's thread whenever `idle_every` has passed without
  // a job (the VTK trajectories, rewritten while a slow run makes no frames), and after each job.
  explicit AsyncWriter(Limits limits, std::function<void()> idle = {},
                       std::chrono::milliseconds idle_every = std::chrono::milliseconds(0));
  // Finishes if finish() was not called; an error is then dropped.
  ~AsyncWriter();
  AsyncWriter(const AsyncWriter&) = delete;
  AsyncWriter& operator=(const AsyncWriter&) = delete;

  // Queues `job` (its data `bytes` long), waiting for room; drops it once the writer has failed.
  void push(size_t bytes, std::function<void()> job);
  // A job has thrown: the run may as well stop.
  bool failed() const;
  // Waits for every job and stops the thread; rethrows the first job's error. Calling it again
  // does nothing.
  void finish();
  // Runs `closing` on the caller's thread after the writer has stopped, also after an error (the
  // .pvd that lists the frames written until then); its error is kept when it is the first.
  void finish(const std::function<void()>& closing);
  Use high_water() const;
  size_t job_bound() const { return limits_.jobs; }

 private:
  struct Job {
    size_t bytes;
    std::function<void()> run;
  };
  void loop();
  void fail(std::exception_ptr e);

  const Limits limits_;
  const std::function<void()> idle_;
  const std::chrono::milliseconds idle_every_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;  // a job queued, or stop
  std::condition_variable room_;  // a job taken, or a failure
  std::deque<Job> queue_;
  size_t queued_bytes_ = 0;
  Use high_water_;
  bool stop_ = false;
  bool failed_ = false;
  bool finished_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // last: started once the rest is ready
};

}  // namespace aeroflock
