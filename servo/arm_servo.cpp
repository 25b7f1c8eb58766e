#include "servo/arm_servo.h"

#include <algorithm>
#include <cmath>

#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {

void ServoConfig::Validate(const std::string& source) const {
  CheckRange(source, "servo.gain_per_s", gain_per_s, 1e-6, 50.0, "1/s");
  CheckRange(source, "servo.switch_blend_per_s", switch_blend_per_s, 1e-6, 100.0, "1/s");
  CheckRange(source, "servo.damping.singular_threshold", damping.singular_threshold, 1e-9, 1.0, "");
  CheckRange(source, "servo.damping.max_damping", damping.max_damping, 1e-9, 1.0, "");
  CheckRange(source, "servo.speed_fraction", speed_fraction, 1e-6, 1.0, "");
  CheckRange(source, "servo.max_accel_rad_s2", max_accel_rad_s2, 1e-6, 1000.0, "rad/s^2");
  CheckRange(source, "servo.limit_zone_rad", limit_zone_rad, 0.0, 1.0, "rad");
  CheckRange(source, "servo.limit_gain_per_s", limit_gain_per_s, 0.0, 100.0, "1/s");
  for (int i = 0; i < 3; ++i) {
    CheckRange(source, "servo.orientation_weights[" + std::to_string(i) + "]",
               orientation_weights[i], 0.0, 1.0, "");
  }
  CheckRange(source, "servo.stale_target_s", stale_target_s, 1e-6, 10.0, "s");
}

const char* ServoStatusName(ServoStatus status) {
  switch (status) {
    case ServoStatus::kMoving: return "moving";
    case ServoStatus::kNoTarget: return "no target";
    case ServoStatus::kStaleTarget: return "stale target";
    case ServoStatus::kInvalidTarget: return "invalid target";
    case ServoStatus::kInvalidState: return "invalid joint state";
    case ServoStatus::kSafeVolume: return "safe volume";
  }
  return "?";
}

ArmServo::ArmServo(const ArmModel& arm, const ServoConfig& config, ForbiddenPredicate forbidden)
    : arm_(arm), config_(config), forbidden_(std::move(forbidden)), pbvs_(config.gain_per_s) {
  config_.Validate("servo config");
  Reset();
}

void ArmServo::Reset() {
  last_dq_ = Eigen::VectorXd::Zero(arm_.dof());
  switch_dq_ = Eigen::VectorXd::Zero(arm_.dof());
  switch_time_s_ = -1.0;
  switch_pending_ = false;
}

void ArmServo::SetTarget(const Eigen::Isometry3d& bMg, double stamp_s, bool is_switch) {
  if (is_switch && has_target_) {
    // The previous command fades out from the first step after the switch.
    switch_dq_ = last_dq_;
    switch_pending_ = true;
  }
  bMg_ = bMg;
  target_stamp_s_ = stamp_s;
  has_target_ = true;
}

ServoStatus ArmServo::Hold(const Eigen::VectorXd& q, ServoStatus status, ServoCommand* out) {
  out->dq_rad_s = Eigen::VectorXd::Zero(arm_.dof());
  out->q_target_rad = q;
  out->step_scale = 0.0;
  last_dq_.setZero();
  return status;
}

ServoStatus ArmServo::Step(const Eigen::VectorXd& q, double now_s, double dt_s,
                           ServoCommand* out) {
  const int n = arm_.dof();
  if (q.size() != n || !q.allFinite()) {
    return Hold(last_good_q_.size() == n ? last_good_q_ : Eigen::VectorXd::Zero(n),
                ServoStatus::kInvalidState, out);
  }
  last_good_q_ = q;
  if (!(dt_s > 0.0) || !std::isfinite(now_s)) return Hold(q, ServoStatus::kInvalidState, out);
  if (!has_target_) return Hold(q, ServoStatus::kNoTarget, out);
  if (!IsValidTransform(bMg_, 1e-6)) return Hold(q, ServoStatus::kInvalidTarget, out);
  if (now_s - target_stamp_s_ > config_.stale_target_s) return Hold(q, ServoStatus::kStaleTarget, out);

  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, n);
  arm_.Kinematics(q, &bMe, &J);
  const Eigen::Matrix<double, 6, 1> twist = pbvs_.Twist(bMe, bMg_);
  const PoseError error = ComparePoses(bMe, bMg_);
  out->position_error_m = error.translation_m;
  out->rotation_error_rad = error.rotation_rad;

  // Joint weights for limit avoidance (weighted least norm): a joint inside the
  // zone near a limit and still moving toward it gets a small weight.
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  Eigen::VectorXd away = Eigen::VectorXd::Zero(n);  // push out of the zone
  for (int i = 0; i < n; ++i) {
    const double to_lower = q[i] - arm_.lower_limits()[i];
    const double to_upper = arm_.upper_limits()[i] - q[i];
    const double zone = config_.limit_zone_rad;
    if (zone <= 0.0) continue;
    if (to_lower < zone && last_dq_[i] <= 0.0) {
      w[i] = std::max(0.05, to_lower / zone);
      away[i] = config_.limit_gain_per_s * (zone - to_lower);
    } else if (to_upper < zone && last_dq_[i] >= 0.0) {
      w[i] = std::max(0.05, to_upper / zone);
      away[i] = -config_.limit_gain_per_s * (zone - to_upper);
    }
  }
  const Eigen::MatrixXd sqrt_w = w.cwiseSqrt().asDiagonal();

  // Position first; orientation (weighted about the tool axes) in what is left.
  const Eigen::Matrix3d bRe = bMe.linear();
  const Eigen::Matrix3d W_b = bRe * config_.orientation_weights.asDiagonal() * bRe.transpose();
  const Eigen::MatrixXd J1 = J.topRows<3>() * sqrt_w;
  const Eigen::MatrixXd J2 = W_b * J.bottomRows<3>() * sqrt_w;
  const DlsSolution solution =
      SolvePrioritized(J1, twist.head<3>(), J2, W_b * twist.tail<3>(), config_.damping);
  Eigen::VectorXd dq = sqrt_w * solution.dq + away;
  out->damping = solution.damping;
  out->min_singular = solution.min_singular;

  // Continuous sequencing at a grasp switch: the old command fades out.
  if (switch_pending_) {  // first step after a switch: fade what differs from the new command
    switch_dq_ -= dq;
    switch_time_s_ = now_s;
    switch_pending_ = false;
  }
  if (switch_time_s_ >= 0.0) {
    const double fade = std::exp(-config_.switch_blend_per_s * (now_s - switch_time_s_));
    dq += switch_dq_ * fade;
    if (fade < 1e-4) switch_time_s_ = -1.0;
  }

  // Speed limits (uniform scaling keeps the direction), then acceleration limits.
  double scale = 1.0;
  for (int i = 0; i < n; ++i) {
    const double vmax = config_.speed_fraction * arm_.velocity_limits()[i];
    if (std::abs(dq[i]) > vmax) scale = std::min(scale, vmax / std::abs(dq[i]));
  }
  dq *= scale;
  const double max_change = config_.max_accel_rad_s2 * dt_s;
  dq = last_dq_ + (dq - last_dq_).cwiseMax(-max_change).cwiseMin(max_change);
  // Never step past a joint limit.
  for (int i = 0; i < n; ++i) {
    const double next = q[i] + dq[i] * dt_s;
    if (next > arm_.upper_limits()[i]) dq[i] = std::min(0.0, (arm_.upper_limits()[i] - q[i]) / dt_s);
    if (next < arm_.lower_limits()[i]) dq[i] = std::max(0.0, (arm_.lower_limits()[i] - q[i]) / dt_s);
  }

  // The safe volume: shorten the step until it is allowed, else hold.
  double step = 1.0;
  if (forbidden_) {
    while (step > 0.1 && forbidden_(q + step * dq * dt_s)) step *= 0.5;
    if (step <= 0.1) return Hold(q, ServoStatus::kSafeVolume, out);
    dq *= step;
  }
  out->step_scale = scale * step;
  out->dq_rad_s = dq;
  out->q_target_rad = q + dq * dt_s;
  last_dq_ = dq;
  return ServoStatus::kMoving;
}

}  // namespace aerograsp
