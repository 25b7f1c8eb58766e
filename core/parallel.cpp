#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace aerograsp {

void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
  if (n == 0) return;
  if (n == 1) {
    fn(0);
    return;
  }
  // Grain 1: each index is a task the scheduler may hand to an idle thread, the
  // callers' items being few and costly (registrations, hypotheses). A throwing
  // call cancels the group and TBB rethrows the first exception here.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                    [&fn](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) fn(i);
                    });
}

}  // namespace aerograsp
