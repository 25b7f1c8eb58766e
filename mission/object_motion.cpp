#include "mission/object_motion.h"

#include <algorithm>

namespace aerograsp {

Eigen::Vector3d AxisMotion::Constrain(const Eigen::Vector3d& p_w, double t_s) const {
  return p_w + (At(t_s) - axis_w.dot(p_w)) * axis_w;
}

std::optional<AxisMotion> FitAxisMotion(const std::vector<StampedPosition>& positions,
                                        const Eigen::Vector3d& axis_w, int min_samples) {
  const double norm = axis_w.norm();
  if (static_cast<int>(positions.size()) < std::max(2, min_samples) || !(norm > 0.0))
    return std::nullopt;
  AxisMotion m;
  m.axis_w = axis_w / norm;
  m.t0_s = positions.front().stamp_s;
  for (const StampedPosition& p : positions) m.t0_s = std::max(m.t0_s, p.stamp_s);
  // Centred sums: the line through the means with the least-squares slope.
  const double n = static_cast<double>(positions.size());
  double mean_t = 0.0, mean_s = 0.0;
  for (const StampedPosition& p : positions) {
    mean_t += (p.stamp_s - m.t0_s) / n;
    mean_s += m.axis_w.dot(p.p_w) / n;
  }
  double stt = 0.0, sts = 0.0;
  for (const StampedPosition& p : positions) {
    const double dt = p.stamp_s - m.t0_s - mean_t;
    stt += dt * dt;
    sts += dt * (m.axis_w.dot(p.p_w) - mean_s);
  }
  if (!(stt > 1e-12)) return std::nullopt;
  m.v_mps = sts / stt;
  m.s0_m = mean_s - m.v_mps * mean_t;  // at t0_s
  return m;
}

}  // namespace aerograsp
