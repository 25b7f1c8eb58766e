#include "servo/grasp_sequence.h"

#include "core/config.h"

namespace aerograsp {

void GraspSequenceConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "precatch_distance_m", precatch_distance_m, 1e-6, 0.5, "m");
  precatch_tolerance.Validate(source, prefix + "precatch_tolerance.");
  grasp_tolerance.Validate(source, prefix + "grasp_tolerance.");
  CheckRange(source, prefix + "precatch_timeout_s", precatch_timeout_s, 1e-6, 600.0, "s");
  CheckRange(source, prefix + "grasp_timeout_s", grasp_timeout_s, 1e-6, 600.0, "s");
  CheckRange(source, prefix + "close_time_s", close_time_s, 1e-6, 10.0, "s");
}

const char* GraspPhaseName(GraspPhase phase) {
  switch (phase) {
    case GraspPhase::kPreCatch:
      return "pre-catch";
    case GraspPhase::kGrasp:
      return "grasp";
    case GraspPhase::kClose:
      return "close";
    case GraspPhase::kDone:
      return "done";
    case GraspPhase::kTimedOut:
      return "timed out";
  }
  return "?";
}

GraspSequence::GraspSequence(ArmServo* servo, const GraspSequenceConfig& config)
    : servo_(servo), config_(config) {
  config_.Validate("grasp sequence config", "grasp_sequence.");
}

void GraspSequence::Start(double now_s) {
  servo_->Reset();
  target_on_object_ = true;
  hold_at_grasp_ = false;
  Enter(GraspPhase::kPreCatch, now_s);
}

void GraspSequence::Enter(GraspPhase phase, double now_s) {
  phase_ = phase;
  phase_start_s_ = now_s;
}

void GraspSequence::GripperHolds(double now_s) {
  if (phase_ == GraspPhase::kClose) Enter(GraspPhase::kDone, now_s);
}

void GraspSequence::SetGrasp(const Eigen::Isometry3d& bMg, double stamp_s, bool is_switch) {
  SetGrasp(bMg, PreCatchPose(bMg), stamp_s, is_switch);
}

void GraspSequence::SetGrasp(const Eigen::Isometry3d& bMg, const Eigen::Isometry3d& bMp,
                             double stamp_s, bool is_switch) {
  bMg_ = bMg;
  bMp_ = bMp;
  grasp_stamp_s_ = stamp_s;
  switch_pending_ = switch_pending_ || (is_switch && has_grasp_);
  has_grasp_ = true;
}

Eigen::Isometry3d GraspSequence::PreCatchPose(const Eigen::Isometry3d& bMg) const {
  return bMg * Eigen::Translation3d(0.0, 0.0, -config_.precatch_distance_m);
}

GraspPhase GraspSequence::Step(const Eigen::VectorXd& q, double now_s, double dt_s,
                               GraspCommand* out) {
  if (switch_pending_ && (phase_ == GraspPhase::kGrasp || phase_ == GraspPhase::kClose)) {
    Enter(GraspPhase::kPreCatch, now_s);  // approach the new grasp along its own axis
  }
  const bool hold_only = phase_ == GraspPhase::kDone || phase_ == GraspPhase::kTimedOut;
  if (has_grasp_ && !hold_only) {
    servo_->SetTarget(phase_ == GraspPhase::kPreCatch ? bMp_ : bMg_, grasp_stamp_s_,
                      switch_pending_);
    switch_pending_ = false;
  }
  if (hold_only && q.allFinite()) {
    // Holding after the end: no motion, the joints as they are as targets.
    out->joints.dq_rad_s = Eigen::VectorXd::Zero(q.size());
    out->joints.q_target_rad = q;
    out->servo_status = ServoStatus::kMoving;
  } else {  // (an invalid q while holding: the servo holds the last good one)
    out->servo_status = servo_->Step(q, now_s, dt_s, &out->joints);
  }
  const double in_phase_s = now_s - phase_start_s_;
  const bool moving = out->servo_status == ServoStatus::kMoving;
  // A servoing phase ends when its pose is met, or in a timeout.
  const auto advance = [&](const PoseTolerance& tolerance, double timeout_s, GraspPhase next) {
    if (moving && tolerance.Met(out->joints.error)) {
      Enter(next, now_s);
    } else if (in_phase_s > timeout_s) {
      Enter(GraspPhase::kTimedOut, now_s);
    }
  };
  at_precatch_ = phase_ == GraspPhase::kPreCatch && moving &&
                 config_.precatch_tolerance.Met(out->joints.error);
  at_grasp_ = phase_ == GraspPhase::kGrasp && moving && target_on_object_ &&
              config_.grasp_tolerance.Met(out->joints.error);
  switch (phase_) {
    case GraspPhase::kPreCatch:
      if (at_precatch_ && hold_at_precatch_) {
        phase_start_s_ = now_s;  // waiting for the other arm does not count against the timeout
      } else {
        advance(config_.precatch_tolerance, config_.precatch_timeout_s, GraspPhase::kGrasp);
      }
      break;
    case GraspPhase::kGrasp:
      if (at_grasp_ && hold_at_grasp_) {
        if (in_phase_s > config_.grasp_timeout_s) Enter(GraspPhase::kTimedOut, now_s);
      } else if (target_on_object_) {
        advance(config_.grasp_tolerance, config_.grasp_timeout_s, GraspPhase::kClose);
      } else if (in_phase_s > config_.grasp_timeout_s) {
        Enter(GraspPhase::kTimedOut, now_s);
      }
      break;
    case GraspPhase::kClose:
      if (in_phase_s >= config_.close_time_s) Enter(GraspPhase::kDone, now_s);
      break;
    case GraspPhase::kDone:
    case GraspPhase::kTimedOut:
      break;
  }
  at_precatch_ = at_precatch_ && phase_ == GraspPhase::kPreCatch;
  at_grasp_ = at_grasp_ && phase_ == GraspPhase::kGrasp;
  if (phase_ == GraspPhase::kTimedOut && !hold_only && moving) {
    out->joints.dq_rad_s = Eigen::VectorXd::Zero(q.size());
    out->joints.q_target_rad = q;
    servo_->Reset();
  }
  out->gripper = phase_ == GraspPhase::kClose || phase_ == GraspPhase::kDone
                     ? GripperCommand::kClose
                     : GripperCommand::kOpen;
  out->phase = phase_;
  out->phase_time_s = now_s - phase_start_s_;
  return phase_;
}

}  // namespace aerograsp
