// parallelFor and analysisThreads (parallel.h). CI also runs these under ThreadSanitizer
// (scripts/sanitize.sh), which holds the hand-out of indices and the error path to be free of races.
#include "base/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.h"
#include "base/parallel_test_util.h"

namespace hb {
namespace {

// Each index is written by the one thread that was handed it: a second hand-out of an index would
// count 2 here (and be a data race ThreadSanitizer reports).
TEST(ParallelFor, CallsEveryIndexExactlyOnceWhateverTheThreadCount) {
  for (unsigned threads : {1u, 2u, 3u, 8u, 64u}) {
    const ScopedAnalysisThreads scoped(threads);
    for (size_t n : {size_t(0), size_t(1), size_t(7), size_t(1000)}) {
      std::vector<uint8_t> calls(n, 0);
      parallelFor(n, [&](size_t i) { calls[i]++; });
      for (size_t i = 0; i < n; ++i)
        ASSERT_EQ(calls[i], 1u) << "index " << i << " of " << n << ", " << threads << " threads";
    }
  }
}

// Two indices on two threads run at the same time: each waits (up to 60 s) until the other has
// started, which a serial loop would never see.
TEST(ParallelFor, RunsIndicesAtTheSameTimeOnSeveralThreads) {
  const ScopedAnalysisThreads scoped(2u);
  std::atomic<int> started{0};
  std::vector<uint8_t> sawTheOther(2, 0);
  parallelFor(2, [&](size_t i) {
    started.fetch_add(1);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (started.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    sawTheOther[i] = started.load() == 2;
  });
  EXPECT_EQ(sawTheOther, std::vector<uint8_t>({1, 1}));
}

// The exception of fn comes out of parallelFor once every thread has stopped: reading what the
// calls wrote after it returns is no race, and no index ran twice.
TEST(ParallelFor, RethrowsTheExceptionOfACallAfterEveryThreadStopped) {
  const ScopedAnalysisThreads scoped(4u);
  const size_t n = 10000;
  std::vector<uint8_t> calls(n, 0);
  try {
    parallelFor(n, [&](size_t i) {
      calls[i]++;
      if (i == 100) throw std::runtime_error("index 100");
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "index 100");
  }
  EXPECT_EQ(calls[100], 1u);
  for (size_t i = 0; i < n; ++i) ASSERT_LE(calls[i], 1u) << "index " << i;
}

TEST(AnalysisThreads, IsHybridbenchThreadsFrom1To1024ElseAnInputErrorAndEveryCoreWhenUnset) {
  {
    const ScopedAnalysisThreads scoped("1");
    EXPECT_EQ(analysisThreads(), 1u);
  }
  {
    const ScopedAnalysisThreads scoped("1024");
    EXPECT_EQ(analysisThreads(), 1024u);
  }
  for (const char* bad : {"0", "1025", "-2", "3x", "", "two"}) {
    const ScopedAnalysisThreads scoped(bad);
    EXPECT_THROW(analysisThreads(), InputError) << "HYBRIDBENCH_THREADS=" << bad;
  }
  const ScopedAnalysisThreads unset(nullptr);
  EXPECT_EQ(analysisThreads(), std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace
}  // namespace hb
