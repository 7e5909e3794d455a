#include "output/async_writer.h"

#include <algorithm>
#include <utility>

namespace aeroflock {

AsyncWriter::AsyncWriter(Limits limits, std::function<void()> idle,
                         std::chrono::milliseconds idle_every)
    : limits_{std::max<size_t>(limits.jobs, 1), limits.bytes},
      idle_(std::move(idle)),
      idle_every_(idle_every),
      thread_([this] { loop(); }) {}

AsyncWriter::~AsyncWriter() {
  try {
    finish();
  } catch (...) {
    // Reported by finish() when the owner asks; a destructor must not throw.
  }
}

void AsyncWriter::loop() {
  while (true) {
    Job job{0, {}};
    {
      std::unique_lock lock(mutex_);
      auto ready = [&] { return stop_ || !queue_.empty(); };
      if (idle_ && idle_every_.count() > 0)
        wake_.wait_for(lock, idle_every_, ready);
      else
        wake_.wait(lock, ready);
      if (!queue_.empty()) {
        job = std::move(queue_.front());
        queue_.pop_front();
        queued_bytes_ -= job.bytes;
      } else if (stop_) {
        break;
      }
    }
    room_.notify_all();
    if (failed()) continue;  // drain and drop
    try {
      if (job.run) job.run();
      if (idle_) idle_();
    } catch (...) {
      fail(std::current_exception());
    }
  }
}

void AsyncWriter::fail(std::exception_ptr e) {
  {
    std::lock_guard lock(mutex_);
    if (!error_) error_ = e;
    failed_ = true;
  }
  room_.notify_all();  // a push waiting for room gives up
}

void AsyncWriter::push(size_t bytes, std::function<void()> job) {
  {
    std::unique_lock lock(mutex_);
    room_.wait(lock, [&] {
      return failed_ || (queue_.size() < limits_.jobs &&
                         (queue_.empty() || queued_bytes_ + bytes <= limits_.bytes));
    });
    if (failed_) return;
    queued_bytes_ += bytes;
    queue_.push_back({bytes, std::move(job)});
    high_water_.jobs = std::max(high_water_.jobs, queue_.size());
    high_water_.bytes = std::max(high_water_.bytes, queued_bytes_);
  }
  wake_.notify_one();
}

bool AsyncWriter::failed() const {
  std::lock_guard lock(mutex_);
  return failed_;
}

AsyncWriter::Use AsyncWriter::high_water() const {
  std::lock_guard lock(mutex_);
  return high_water_;
}

void AsyncWriter::finish() { finish({}); }

void AsyncWriter::finish(const std::function<void()>& closing) {
  if (finished_) return;
  finished_ = true;
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
  if (closing) try {
      closing();
    } catch (...) {
      fail(std::current_exception());
    }
  if (error_) std::rethrow_exception(error_);
}

}  // namespace aeroflock
