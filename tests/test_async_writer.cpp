// The outputs' writer thread (engine/output/async_writer.h) in-process: jobs done in order off the
// caller's thread, the queue's bound, the first error stopping it and coming back from finish(),
// the closing work after it, and the idle call.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "output/async_writer.h"

namespace aeroflock {
namespace {

using namespace std::chrono_literals;

TEST(AsyncWriter, DoesEveryJobInOrderOnAThreadOfItsOwn) {
  std::vector<int> done;
  std::vector<std::thread::id> threads;
  AsyncWriter writer({.jobs = 2});
  for (int i = 0; i < 100; ++i)
    writer.push(1, [&, i] {
      done.push_back(i);
      threads.push_back(std::this_thread::get_id());
    });
  writer.finish();
  ASSERT_EQ(done.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(done[i], i);
  for (std::thread::id t : threads) EXPECT_NE(t, std::this_thread::get_id());
  EXPECT_LE(writer.high_water().jobs, 2u);  // push waited for room
}

TEST(AsyncWriter, HoldsNoMoreBytesThanItsBoundButTakesAnyJobWhenEmpty) {
  std::atomic<bool> release{false};
  AsyncWriter writer({.jobs = 8, .bytes = 100});
  writer.push(1, [&] {
    while (!release) std::this_thread::sleep_for(1ms);  // a slow disk
  });
  std::this_thread::sleep_for(20ms);                  // the slow job is taken: the queue is empty
  writer.push(300, [] {});                            // larger than the bound, into an empty queue
  std::thread more([&] { writer.push(60, [] {}); });  // waits: 300 + 60 > 100
  std::this_thread::sleep_for(20ms);
  EXPECT_EQ(writer.high_water().bytes, 300u);
  release = true;
  more.join();
  writer.finish();
  EXPECT_EQ(writer.high_water().bytes, 300u);
}

TEST(AsyncWriter, TheFirstErrorStopsItAndFinishThrowsItAfterTheClosingWork) {
  std::vector<int> done;
  bool closed = false;
  AsyncWriter writer({.jobs = 1});
  writer.push(1, [&] { done.push_back(1); });
  writer.push(1, [] { throw std::runtime_error("cannot write a.png: No space left on device"); });
  while (!writer.failed()) std::this_thread::sleep_for(1ms);
  writer.push(1, [&] { done.push_back(3); });  // dropped
  try {
    writer.finish([&] {
      closed = true;
      throw std::runtime_error("cannot write flock.pvd: No space left on device");  // not first
    });
    FAIL() << "finish() did not throw";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "cannot write a.png: No space left on device");
  }
  EXPECT_TRUE(closed);
  EXPECT_EQ(done, std::vector<int>{1});
  EXPECT_NO_THROW(writer.finish());  // again: nothing
}

TEST(AsyncWriter, AClosingErrorIsTheErrorWhenNoJobFailed) {
  AsyncWriter writer({});
  writer.push(1, [] {});
  EXPECT_THROW(writer.finish([] { throw std::runtime_error("closing"); }), std::runtime_error);
}

TEST(AsyncWriter, CallsIdleWhileNoJobComesAndAfterEachJob) {
  std::atomic<int> idle{0};
  AsyncWriter writer(
      {}, [&] { ++idle; }, 5ms);
  std::this_thread::sleep_for(60ms);
  EXPECT_GE(idle.load(), 3);
  const int before = idle;
  writer.push(1, [] {});
  writer.finish();
  EXPECT_GT(idle.load(), before);
}

}  // namespace
}  // namespace aeroflock
