// Independent work items spread over the machine's cores.
#pragma once

#include <cstddef>
#include <functional>

namespace aerograsp {

/// Calls fn(i) once for every i in [0, n) on oneTBB's shared worker pool (the
/// calling thread takes part; the pool is started once per process, so a call
/// costs microseconds, not a thread start). The calls must not depend on one
/// another and may run in any order; a caller that keeps their results by index
/// gets the same results as a loop. The first exception thrown by a call is
/// rethrown here after every running call has returned; calls not yet started
/// are skipped. A call nested inside another ParallelFor is allowed.
void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& fn);

}  // namespace aerograsp
