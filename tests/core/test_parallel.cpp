#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/parallel.h"

namespace aerograsp {
namespace {

TEST(ParallelForTest, EveryIndexRunsOnceAndResultsKeptByIndexMatchALoop) {
  const std::size_t n = 1000;
  std::vector<double> loop(n), parallel(n);
  auto work = [](std::size_t i) {
    double x = 0.0;
    for (std::size_t k = 0; k <= i % 97; ++k) x += std::sin(double(i * k));  // uneven costs
    return x;
  };
  for (std::size_t i = 0; i < n; ++i) loop[i] = work(i);
  std::vector<std::atomic<int>> calls(n);
  ParallelFor(n, [&](std::size_t i) {
    ++calls[i];
    parallel[i] = work(i);
  });
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(calls[i].load(), 1) << i;
    EXPECT_EQ(parallel[i], loop[i]) << i;
  }
}

TEST(ParallelForTest, NoWorkCallsNothing) {
  int calls = 0;
  ParallelFor(0, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(ParallelForTest, UsesAnotherThreadWhenTheMachineHasOne) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core";
  std::set<std::thread::id> seen;
  std::mutex m;
  std::atomic<int> arrived{0};
  ParallelFor(2, [&](std::size_t) {
    {
      std::lock_guard<std::mutex> lock(m);
      seen.insert(std::this_thread::get_id());
    }
    // Each call waits (up to 5 s) for the other: with two threads they meet.
    ++arrived;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (arrived.load() < 2 && std::chrono::steady_clock::now() < give_up)
      std::this_thread::yield();
  });
  EXPECT_EQ(seen.size(), 2u);
}

TEST(ParallelForTest, AThrownErrorReachesTheCallerWithItsTypeAndMessage) {
  std::atomic<int> calls{0};
  try {
    ParallelFor(100, [&](std::size_t i) {
      ++calls;
      if (i == 3) throw std::out_of_range("item 3 failed");
    });
    FAIL() << "no exception reached the caller";
  } catch (const std::out_of_range& e) {
    EXPECT_STREQ(e.what(), "item 3 failed");
  }
  EXPECT_GE(calls.load(), 1);
  EXPECT_LE(calls.load(), 100);
}

TEST(ParallelForTest, NestedCallsRunEveryInnerIndex) {
  const std::size_t outer = 6, inner = 50;
  std::vector<std::atomic<int>> calls(outer * inner);
  ParallelFor(outer, [&](std::size_t i) {
    ParallelFor(inner, [&](std::size_t j) { ++calls[i * inner + j]; });
  });
  for (std::size_t k = 0; k < calls.size(); ++k) EXPECT_EQ(calls[k].load(), 1) << k;
}

}  // namespace
}  // namespace aerograsp
