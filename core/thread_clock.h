// CPU time of the calling thread, for timing stages without counting the time
// other processes take from this core (the development machine is shared).
#pragma once

#include <time.h>

namespace aerograsp {

/// Milliseconds of CPU time used by the calling thread (CLOCK_THREAD_CPUTIME_ID).
inline double ThreadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

/// Milliseconds of CPU time used by all the process's threads
/// (CLOCK_PROCESS_CPUTIME_ID): a stage spread over the cores counts whole.
inline double ProcessCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

}  // namespace aerograsp
