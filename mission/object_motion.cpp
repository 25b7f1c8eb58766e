#include "mission/object_motion.h"

#include <algorithm>
#include <cmath>
#include <utility>

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

void LengthMotion::DropOlderThan(double stamp_s) {
  frames_.erase(std::remove_if(frames_.begin(), frames_.end(),
                               [&](const StampedPosition& p) { return p.stamp_s < stamp_s; }),
                frames_.end());
}

bool LengthMotion::Add(const StampedPosition& frame) {
  if (motion_) {
    const double off_m = motion_->axis_w.dot(frame.p_w) - motion_->At(frame.stamp_s);
    if (std::abs(off_m) > options_.break_m) {
      disagreeing_.push_back(frame);
      if (static_cast<int>(disagreeing_.size()) < options_.break_frames) return false;
      // The motion changed: the fit starts again from these frames.
      frames_ = std::move(disagreeing_);
      disagreeing_.clear();
      ++breaks_;
      Refit();
      return true;
    }
    disagreeing_.clear();
  }
  frames_.push_back(frame);
  DropOlderThan(frame.stamp_s - options_.window_s);
  if (motion_) Refit();
  return false;
}

void LengthMotion::Refit() {
  if (auto fit = FitAxisMotion(frames_, motion_->axis_w, options_.refit_min_frames)) {
    motion_ = fit;
    return;
  }
  if (breaks_ == 0) return;  // the locked fit stands
  // Too few frames since the motion changed for a speed: it stands where they put it.
  double s_m = 0.0, t0_s = frames_.front().stamp_s;
  for (const StampedPosition& p : frames_) {
    s_m += motion_->axis_w.dot(p.p_w) / static_cast<double>(frames_.size());
    t0_s = std::max(t0_s, p.stamp_s);
  }
  motion_->t0_s = t0_s;
  motion_->s0_m = s_m;
  motion_->v_mps = 0.0;
}

bool LengthMotion::Lock(const Eigen::Vector3d& axis_w) {
  motion_ = FitAxisMotion(frames_, axis_w, options_.lock_min_frames);
  disagreeing_.clear();
  breaks_ = 0;
  return motion_.has_value();
}

void LengthMotion::Reset() {
  frames_.clear();
  disagreeing_.clear();
  motion_.reset();
  breaks_ = 0;
}

double EmptyCloseShiftM(double x_tool_m, double x_min_m, double x_max_m, double max_shift_m) {
  if (x_tool_m <= x_min_m || x_tool_m >= x_max_m) return 0.0;
  const double to_max = x_max_m - x_tool_m, to_min = x_tool_m - x_min_m;
  if (std::min(to_max, to_min) > max_shift_m) return 0.0;
  return to_max <= to_min ? -to_max : to_min;
}

}  // namespace aerograsp
