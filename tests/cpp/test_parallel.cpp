// parallel_for: one parallel region, progress from the calling thread, cancellation, and the
// exception of the lowest job index whatever the thread count.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "drill/parallel.hpp"

using drill::parallel_for;

TEST(ParallelFor, EveryJobRunsOnceAndProgressEndsAtTheTotalOnTheCallingThread) {
  for (int threads : {1, 2, 3}) {
    std::vector<int> runs(37, 0);
    std::vector<std::size_t> reported;
    const std::thread::id caller = std::this_thread::get_id();
    bool other_thread = false;
    const bool done = parallel_for(
        runs.size(), [&](std::size_t i) { ++runs[i]; },
        [&](std::size_t d, std::size_t n) {
          EXPECT_EQ(n, runs.size());
          other_thread |= std::this_thread::get_id() != caller;
          reported.push_back(d);
          return true;
        },
        threads, 5);
    EXPECT_TRUE(done);
    EXPECT_EQ(runs, std::vector<int>(37, 1)) << threads << " threads";
    EXPECT_FALSE(other_thread);
    ASSERT_FALSE(reported.empty());
    EXPECT_EQ(reported.back(), runs.size());
    for (std::size_t k = 1; k < reported.size(); ++k) EXPECT_GT(reported[k], reported[k - 1]);
  }
}

// A job on a thread other than the caller's holds until the callback has cancelled (or 10 s
// passed), and 0.1 s more for parallel_for to see the cancel: the jobs then finish in a known
// order whatever the scheduling.
struct HeldJobs {
  std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> cancelled{false};
  std::atomic<std::size_t> ran{0};
  void operator()(std::size_t) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::this_thread::get_id() != caller && !cancelled && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    if (std::this_thread::get_id() != caller) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ++ran;
  }
};

TEST(ParallelFor, ACancelStopsTakingJobs) {
  for (int threads : {1, 2}) {
    HeldJobs jobs;
    const bool done = parallel_for(
        1000, [&](std::size_t i) { jobs(i); },
        [&](std::size_t d, std::size_t) {
          jobs.cancelled = d >= 4;
          return !jobs.cancelled;
        },
        threads, 1);
    EXPECT_FALSE(done);
    // the caller runs 4 jobs and cancels; another thread finishes the one job it holds, if it took one
    EXPECT_GE(jobs.ran.load(), 4u);
    EXPECT_LE(jobs.ran.load(), 3u + static_cast<std::size_t>(threads)) << threads << " threads";
  }
}

TEST(ParallelFor, AThrowingCallbackCancelsAndIsRethrown) {
  HeldJobs jobs;
  EXPECT_THROW(parallel_for(
                   1000, [&](std::size_t i) { jobs(i); },
                   [&](std::size_t, std::size_t) -> bool {
                     jobs.cancelled = true;
                     throw std::runtime_error("interrupted");
                   },
                   2, 1),
               std::runtime_error);
  EXPECT_GE(jobs.ran.load(), 1u);  // the caller's job, and the other thread's if it took one
  EXPECT_LE(jobs.ran.load(), 2u);
}

TEST(ParallelFor, TheLowestFailingJobsErrorIsRethrownOnAnyThreadCount) {
  for (int threads : {1, 2, 4}) {
    std::string what;
    try {
      parallel_for(
          64,
          [](std::size_t i) {
            if (i == 41 || i == 17 || i == 60) throw std::invalid_argument("job " + std::to_string(i));
          },
          nullptr, threads);
    } catch (const std::invalid_argument& e) {
      what = e.what();
    }
    EXPECT_EQ(what, "job 17") << threads << " threads";
  }
}
