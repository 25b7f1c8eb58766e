// Order statistics of timing and error samples for the commands' reports.
#pragma once

#include <vector>

namespace aerograsp {

/// The sample at rank round(fraction * (n - 1)) of the sorted values (nearest
/// rank: 0.5 is the median, v[n / 2]); `if_empty` when there are none.
double Percentile(std::vector<double> values, double fraction, double if_empty = 0.0);

}  // namespace aerograsp
