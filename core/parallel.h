// Independent work items spread over the machine's cores.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace aerograsp {

/// Calls fn(i) once for every i in [0, n), on the calling thread and up to
/// hardware_concurrency() - 1 helpers, each taking the next index as it gets
/// free. The calls must not depend on one another; a caller that keeps their
/// results by index gets the same results as a loop. The first exception
/// thrown by a call is rethrown here once all threads have stopped.
template <typename Fn>
void ParallelFor(std::size_t n, Fn&& fn) {
  const std::size_t threads =
      std::min<std::size_t>(n, std::max(1u, std::thread::hardware_concurrency()));
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;  // written once, by the thread that set `failed`
  auto work = [&] {
    for (std::size_t i = next++; i < n && !failed.load(); i = next++) {
      try {
        fn(i);
      } catch (...) {
        if (!failed.exchange(true)) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace aerograsp
