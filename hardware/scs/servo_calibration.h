// Joint angle <-> raw servo ticks through a per-joint calibration, as the
// original arms did it (docs/hardware.md): two measured angles per joint, the joint
// angle at raw 0 and at raw 1023; linear in between. A reversed servo has
// angle_at_max_rad < angle_at_min_rad.
#pragma once

#include <algorithm>
#include <cmath>

namespace aerograsp {

constexpr int kScsMaxRaw = 1023;  ///< 10-bit positions

struct ServoCalibration {
  int id = 0;                     ///< bus id, [0, 253]
  double angle_at_min_rad = 0.0;  ///< joint angle measured with the servo at raw 0, rad
  /// joint angle measured at raw 1023, rad (differs from the other)
  double angle_at_max_rad = 0.0;

  /// Nearest raw position of `q_rad`, clamped to [0, 1023].
  int RawFromAngle(double q_rad) const {
    const double t = (q_rad - angle_at_min_rad) / (angle_at_max_rad - angle_at_min_rad);
    return std::clamp(static_cast<int>(std::lround(t * kScsMaxRaw)), 0, kScsMaxRaw);
  }
  double AngleFromRaw(int raw) const {
    return angle_at_min_rad + (angle_at_max_rad - angle_at_min_rad) * raw / double(kScsMaxRaw);
  }
};

/// The gripper servo: a screw drives the fingers, so only the two ends matter.
struct GripperServoConfig {
  int id = 0;            ///< bus id, [0, 253]
  int raw_open = 1023;   ///< fingers fully open (SCS: 1023), [0, 1023]
  int raw_closed = 350;  ///< fingers closed (SCS: ~350), [0, 1023], differs from raw_open
};

}  // namespace aerograsp
