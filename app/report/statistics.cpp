#include "app/report/statistics.h"

#include <algorithm>

namespace aerograsp {

double Percentile(std::vector<double> values, double fraction, double if_empty) {
  if (values.empty()) return if_empty;
  const std::size_t k =
      std::min(values.size() - 1, static_cast<std::size_t>(fraction * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace aerograsp
