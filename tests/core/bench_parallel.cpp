// ParallelFor's cost per call against a plain loop, on the shape of work its
// callers give it: a few independent items of tens of microseconds, called
// many times (registrations of coarse candidates, orientation hypotheses).
//   build/tests/aerograsp_core_benchmarks --benchmark_out=parallel.json
// prints the time per call of 8 items of ~50 us; 2,000 calls take 2,000 times that.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <vector>

#include "core/parallel.h"

namespace aerograsp {
namespace {

constexpr std::size_t kItems = 8;
// Terms of the series below: about 50 us of work on one core of a 2020s x86-64.
constexpr int kTermsPerItem = 4000;

double Item(std::size_t i) {
  double sum = 0.0;
  for (int k = 1; k <= kTermsPerItem; ++k) sum += std::sin(double(i + 1) * k) / k;
  return sum;
}

void BM_Item(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(Item(3));
}

void BM_SerialLoop(benchmark::State& state) {
  std::vector<double> results(kItems);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kItems; ++i) results[i] = Item(i);
    benchmark::DoNotOptimize(results.data());
  }
}

void BM_ParallelFor(benchmark::State& state) {
  std::vector<double> results(kItems);
  for (auto _ : state) {
    ParallelFor(kItems, [&](std::size_t i) { results[i] = Item(i); });
    benchmark::DoNotOptimize(results.data());
  }
}

// "Time" is wall time; "CPU" the whole process's CPU time (every thread's), which
// shows what a call costs the machine and stays meaningful on a loaded one.
BENCHMARK(BM_Item)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SerialLoop)
    ->Iterations(2000)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ParallelFor)
    ->Iterations(2000)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace aerograsp

BENCHMARK_MAIN();
