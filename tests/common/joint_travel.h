// How far the arms moved in a time window, from the telemetry a mission sent
// (for the tests that check that an emergency stop stopped them).
#pragma once

#include <algorithm>
#include <vector>

#include "telemetry/telemetry.h"

namespace aerograsp::testing {

/// The largest change of any joint, rad, between the first sample in
/// [from_s, to_s] and any later one in it; 0 with fewer than two samples.
inline double JointTravel(const std::vector<TelemetryArms>& arms, double from_s, double to_s) {
  const TelemetryArms* first = nullptr;
  double travel = 0.0;
  for (const TelemetryArms& a : arms) {
    if (a.t_s < from_s || a.t_s > to_s) continue;
    if (!first) first = &a;
    for (int k = 0; k < 2; ++k) {
      travel = std::max(
          travel, (a.arms[k].position_rad - first->arms[k].position_rad).cwiseAbs().maxCoeff());
    }
  }
  return travel;
}

}  // namespace aerograsp::testing
