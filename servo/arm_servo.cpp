#include "servo/arm_servo.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {

void ServoConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "gain_per_s", gain_per_s, 1e-6, 50.0, "1/s");
  CheckRange(source, prefix + "switch_blend_per_s", switch_blend_per_s, 1e-6, 100.0, "1/s");
  CheckRange(source, prefix + "damping.singular_threshold", damping.singular_threshold, 1e-9, 1.0,
             "");
  CheckRange(source, prefix + "damping.max_damping", damping.max_damping, 1e-9, 1.0, "");
  CheckRange(source, prefix + "speed_fraction", speed_fraction, 1e-6, 1.0, "");
  CheckRange(source, prefix + "max_accel_rad_s2", max_accel_rad_s2, 1e-6, 1000.0, "rad/s^2");
  CheckRange(source, prefix + "limit_zone_rad", limit_zone_rad, 0.0, 1.0, "rad");
  for (int i = 0; i < 3; ++i) {
    CheckRange(source, prefix + "orientation_weights[" + std::to_string(i) + "]",
               orientation_weights[i], 0.0, 1.0, "");
  }
  CheckRange(source, prefix + "stale_target_s", stale_target_s, 1e-6, 10.0, "s");
  CheckRange(source, prefix + "guide_near_rad", guide_near_rad, 0.0, 3.0, "rad");
  CheckRange(source, prefix + "guide_far_rad", guide_far_rad, guide_near_rad + 1e-6, 6.0, "rad");
  CheckRange(source, prefix + "guide_min", guide_min, 0.0, 1.0, "");
  CheckRange(source, prefix + "retarget_m", retarget_m, 0.0, 1.0, "m");
  CheckRange(source, prefix + "retarget_rad", retarget_rad, 0.0, M_PI, "rad");
  CheckRange(source, prefix + "unreachable_retry_s", unreachable_retry_s, 0.0, 60.0, "s");
  CheckRange(source, prefix + "path_check_step_rad", path_check_step_rad, 1e-6, 1.0, "rad");
  CheckRange(source, prefix + "random_vias", random_vias, 0, 1000, "");
  CheckRange(source, prefix + "search_budget", search_budget, 1, 1000000, "");
  CheckRange(source, prefix + "command_lead_rad", command_lead_rad, 0.0, 0.5, "rad");
  ik.Validate(source, prefix + "ik.");
}

const char* ServoStatusName(ServoStatus status) {
  switch (status) {
    case ServoStatus::kMoving:
      return "moving";
    case ServoStatus::kNoTarget:
      return "no target";
    case ServoStatus::kStaleTarget:
      return "stale target";
    case ServoStatus::kInvalidTarget:
      return "invalid target";
    case ServoStatus::kInvalidState:
      return "invalid joint state";
    case ServoStatus::kSafeVolume:
      return "safe volume";
    case ServoStatus::kUnreachable:
      return "unreachable";
    case ServoStatus::kSearching:
      return "searching";
  }
  return "?";
}

ArmServo::ArmServo(const ArmModel& arm, const ServoConfig& config, ForbiddenPredicate forbidden,
                   RightOfWay* right_of_way, int seat)
    : arm_(arm),
      config_(config),
      forbidden_(std::move(forbidden)),
      right_of_way_(right_of_way),
      seat_(seat),
      pbvs_(config.gain_per_s),
      ik_(arm, config.ik, config.orientation_weights) {
  config_.Validate("servo config", "servo.");
  if (seat_ != 0 && seat_ != 1) {
    throw ConfigError("servo config: right-of-way seat " + std::to_string(seat_) +
                      " must be 0 or 1");
  }
  for (std::size_t v = 0; v < config_.via_rad.size(); ++v) {
    if (!arm_.WithinLimits(config_.via_rad[v])) {
      throw ConfigError("servo config: servo.via_rad[" + std::to_string(v) + "]: needs " +
                        std::to_string(arm_.dof()) + " finite joints within the limits of " +
                        arm_.source());
    }
  }
  via_ = config_.via_rad.empty()
             ? std::vector<Eigen::VectorXd>{arm_.Clamp(Eigen::VectorXd::Zero(arm_.dof()))}
             : config_.via_rad;
  std::mt19937 rng(7);
  for (int v = 0; v < config_.random_vias; ++v) via_.push_back(DrawJointsWithinLimits(arm_, &rng));
  Reset();
}

void ArmServo::Reset() {
  last_dq_ = Eigen::VectorXd::Zero(arm_.dof());
  switch_dq_ = Eigen::VectorXd::Zero(arm_.dof());
  switch_time_s_ = -1.0;
  switch_pending_ = false;
  making_way_ = false;
  last_q_target_.resize(0);
}

void ArmServo::SetTarget(const Eigen::Isometry3d& bMg, double stamp_s, bool is_switch) {
  if (is_switch && has_target_) {
    // The previous command fades out from the first step after the switch.
    switch_dq_ = last_dq_;
    switch_pending_ = true;
    search_.active = false;  // another grasp: search again from where the arm is
  }
  bMg_ = bMg;
  target_stamp_s_ = stamp_s;
  has_target_ = true;
}

bool ArmServo::PathAllowed(const Eigen::VectorXd& q_from, const Eigen::VectorXd& q_to) const {
  if (!forbidden_) return true;
  const double length = (q_to - q_from).cwiseAbs().maxCoeff();
  const int samples =
      std::max(1, static_cast<int>(std::ceil(length / config_.path_check_step_rad)));
  for (int k = samples; k >= 1; --k) {  // the goal first: it is the likeliest to be refused
    if (forbidden_(q_from + (q_to - q_from) * (static_cast<double>(k) / samples))) return false;
  }
  return true;
}

namespace {

bool Moved(const Eigen::Isometry3d& aMb_1, const Eigen::Isometry3d& aMb_2, double m, double rad) {
  const PoseError d = ComparePoses(aMb_1, aMb_2);
  return d.translation_m > m || d.rotation_rad > rad;
}

}  // namespace

ArmServo::PathCheck ArmServo::MakePathCheck(const Eigen::VectorXd& from,
                                            const Eigen::VectorXd& to) const {
  PathCheck path;
  path.from = from;
  path.to = to;
  const double length = (to - from).cwiseAbs().maxCoeff();
  path.samples = std::max(1, static_cast<int>(std::ceil(length / config_.path_check_step_rad)));
  path.next = forbidden_ ? path.samples : 0;
  return path;
}

bool ArmServo::StepPath(PathCheck* path, bool* allowed) const {
  *allowed = true;
  if (path->next <= 0) return true;
  const double f = static_cast<double>(path->next) / path->samples;
  if (forbidden_(path->from + (path->to - path->from) * f)) {
    *allowed = false;
    path->next = 0;
    return true;
  }
  return --path->next <= 0;
}

void ArmServo::StartSearch(const Eigen::VectorXd& q) {
  Search& s = search_;
  s = Search{};
  s.active = true;
  s.q_start = q;
  s.seeds = ik_.ClosedFormSeeds(bMg_, q);
  // An arm whose closed form gives every solution (the 6-DoF arm) tries only
  // those: from other seeds the iterations end on one of them or nowhere.
  if (!ik_.closed_form_complete()) {
    s.seeds.push_back(q);
    if (has_goal_) s.seeds.push_back(q_goal_);
    for (const Eigen::VectorXd& hint : hints_) {
      if (hint.size() == q.size()) s.seeds.push_back(hint);
    }
  }
  s.rng.seed(1u);
  s.to_via.assign(via_.size(), -1);
}

bool ArmServo::ContinueSearch(int* budget) {
  Search& s = search_;
  const int n = arm_.dof();
  const std::size_t total =
      s.seeds.size() +
      (ik_.closed_form_complete() ? 0 : static_cast<std::size_t>(config_.ik.random_seeds));
  const auto end = [&](bool found) {
    s.active = false;
    s.found = found;
    return true;
  };
  bool allowed = true;
  while (*budget > 0) {
    switch (s.stage) {
      case Search::Stage::kIk: {
        if (!s.iterating) {
          if (s.next_seed >= total) return end(false);
          const std::size_t k = s.next_seed++;
          const Eigen::VectorXd seed =
              k < s.seeds.size() ? s.seeds[k] : DrawJointsWithinLimits(arm_, &s.rng);
          if (seed.size() != n || !seed.allFinite()) continue;
          s.run = ik_.StartFrom(seed);
          s.iterating = true;
        }
        ik_.Iterate(bMg_, config_.ik.iterations_per_seed, &s.run);
        --*budget;
        if (!s.run.done) break;
        s.iterating = false;
        if (!s.run.best.converged) break;
        // A converged q*: refused already (found again from another seed)?
        const Eigen::VectorXd& q_star = s.run.best.q;
        bool seen = false;
        for (const Eigen::VectorXd& r : s.refused) {
          seen = seen || (r - q_star).cwiseAbs().maxCoeff() <= config_.path_check_step_rad;
        }
        if (seen) break;
        s.refused.push_back(q_star);
        s.candidate = q_star;
        s.path = MakePathCheck(s.q_start, q_star);
        s.stage = Search::Stage::kDirect;
        break;
      }
      case Search::Stage::kDirect:
        if (s.path.next > 0) --*budget;
        if (!StepPath(&s.path, &allowed)) break;
        if (allowed) {
          has_via_ = false;
          return end(true);
        }
        s.via = 0;
        s.stage = Search::Stage::kToVia;
        s.path.next = -1;  // not started
        break;
      case Search::Stage::kToVia:
        if (s.via >= via_.size()) {
          s.stage = Search::Stage::kIk;  // no way to this q*: the next seed
          break;
        }
        if (s.to_via[s.via] < 0) {
          if (s.path.next < 0) s.path = MakePathCheck(s.q_start, via_[s.via]);
          if (s.path.next > 0) --*budget;
          if (!StepPath(&s.path, &allowed)) break;
          s.to_via[s.via] = allowed ? 1 : 0;
        }
        s.path.next = -1;
        if (s.to_via[s.via]) {
          s.stage = Search::Stage::kFromVia;
        } else {
          ++s.via;
        }
        break;
      case Search::Stage::kFromVia:
        if (s.path.next < 0) s.path = MakePathCheck(via_[s.via], s.candidate);
        if (s.path.next > 0) --*budget;
        if (!StepPath(&s.path, &allowed)) break;
        if (allowed) {
          has_via_ = true;
          via_q_ = via_[s.via];
          return end(true);
        }
        ++s.via;
        s.path.next = -1;
        s.stage = Search::Stage::kToVia;
        break;
    }
  }
  return false;
}

ArmServo::Goal ArmServo::UpdateJointGoal(const Eigen::VectorXd& q, double now_s) {
  // Reached via point: on to the next.
  if (has_via_ && (via_q_ - q).cwiseAbs().maxCoeff() <= config_.guide_near_rad) has_via_ = false;
  int budget = config_.search_budget;
  if (!search_.active) {
    if (has_goal_ && goal_bMg_.matrix() == bMg_.matrix()) return Goal::kReady;
    // A target that moved a little: refine q* from itself (a few iterations).
    if (has_goal_) {
      const ApproachIkResult refined = ik_.SolveFrom(bMg_, q_goal_, config_.ik.iterations_per_seed);
      budget -= refined.iterations;
      if (refined.converged &&
          ((refined.q - q_goal_).cwiseAbs().maxCoeff() <= config_.path_check_step_rad ||
           PathAllowed(has_via_ ? via_q_ : q, refined.q))) {
        q_goal_ = refined.q;
        goal_bMg_ = bMg_;
        return Goal::kReady;
      }
    }
    if (!has_goal_ && has_failed_ && now_s - failed_at_s_ < config_.unreachable_retry_s &&
        !Moved(failed_bMg_, bMg_, config_.retarget_m, config_.retarget_rad)) {
      return Goal::kUnreachable;  // searched already, in vain
    }
    // Search: a goal whose straight joint path is allowed, else one reached
    // through a via configuration with both legs allowed.
    StartSearch(q);
  }
  if (!ContinueSearch(&budget)) return has_goal_ ? Goal::kReady : Goal::kSearching;
  has_goal_ = search_.found;
  if (has_goal_) {
    q_goal_ = search_.candidate;
    goal_bMg_ = bMg_;
    has_failed_ = false;
    return Goal::kReady;
  }
  has_failed_ = true;
  failed_bMg_ = bMg_;
  failed_at_s_ = now_s;
  return Goal::kUnreachable;
}

Eigen::VectorXd ArmServo::Limit(const Eigen::VectorXd& q, Eigen::VectorXd dq, double dt_s,
                                double* scale) const {
  // Speed limits (uniform scaling keeps the direction), then acceleration limits.
  *scale = 1.0;
  for (int i = 0; i < arm_.dof(); ++i) {
    const double vmax = config_.speed_fraction * arm_.velocity_limits()[i];
    if (std::abs(dq[i]) > vmax) *scale = std::min(*scale, vmax / std::abs(dq[i]));
  }
  dq *= *scale;
  // The change is scaled as a whole, not clamped joint by joint: from rest the
  // step then keeps the direction of the straight joint path that was checked
  // against the forbidden region (a clamped one bends off it and, next to the
  // other arm, into it).
  const double max_change = config_.max_accel_rad_s2 * dt_s;
  const double change = (dq - last_dq_).cwiseAbs().maxCoeff();
  if (change > max_change) dq = last_dq_ + (dq - last_dq_) * (max_change / change);
  // Never step past a joint limit.
  for (int i = 0; i < arm_.dof(); ++i) {
    const double next = q[i] + dq[i] * dt_s;
    if (next > arm_.upper_limits()[i])
      dq[i] = std::min(0.0, (arm_.upper_limits()[i] - q[i]) / dt_s);
    if (next < arm_.lower_limits()[i])
      dq[i] = std::max(0.0, (arm_.lower_limits()[i] - q[i]) / dt_s);
  }
  return dq;
}

ServoStatus ArmServo::Hold(const Eigen::VectorXd& q, ServoStatus status, ServoCommand* out) {
  out->dq_rad_s = Eigen::VectorXd::Zero(arm_.dof());
  out->q_target_rad = q;
  last_q_target_.resize(0);
  out->step_scale = 0.0;
  out->guide_weight = 0.0;
  out->q_goal_rad = has_goal_ ? q_goal_ : Eigen::VectorXd();
  last_dq_.setZero();
  return status;
}

bool ArmServo::MakeWay(const Eigen::VectorXd& q, double now_s, double to_target_m) {
  if (!right_of_way_ ||
      !right_of_way_->ShouldYield(seat_, now_s, to_target_m, config_.stale_target_s)) {
    return false;
  }
  for (const Eigen::VectorXd& via : via_) {
    if ((via - q).cwiseAbs().maxCoeff() > config_.guide_near_rad && PathAllowed(q, via)) {
      making_way_ = true;
      has_goal_ = false;
      has_via_ = true;
      via_q_ = via;
      return true;
    }
  }
  return false;
}

ServoStatus ArmServo::Step(const Eigen::VectorXd& q, double now_s, double dt_s, ServoCommand* out) {
  const ServoStatus status = Command(q, now_s, dt_s, out);
  if (right_of_way_ && std::isfinite(now_s)) {
    right_of_way_->Post(seat_, now_s,
                        status == ServoStatus::kUnreachable || status == ServoStatus::kSafeVolume,
                        out->position_error_m);
  }
  return status;
}

ServoStatus ArmServo::Command(const Eigen::VectorXd& q, double now_s, double dt_s,
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
  if (now_s - target_stamp_s_ > config_.stale_target_s)
    return Hold(q, ServoStatus::kStaleTarget, out);

  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, n);
  arm_.Kinematics(q, &bMe, &J);
  const PoseError error = ComparePoses(bMe, bMg_);
  out->position_error_m = error.translation_m;
  out->rotation_error_rad = error.rotation_rad;
  out->error = ComputeApproachError(bMe, bMg_);
  if (making_way_ && (via_q_ - q).cwiseAbs().maxCoeff() <= config_.guide_near_rad) {
    making_way_ = has_via_ = has_failed_ = false;  // out of the way: search again from here
  }
  if (!making_way_) {
    const Goal goal = UpdateJointGoal(q, now_s);
    if (goal == Goal::kSearching) return Hold(q, ServoStatus::kSearching, out);
    if (goal == Goal::kUnreachable && !MakeWay(q, now_s, error.translation_m)) {
      return Hold(q, ServoStatus::kUnreachable, out);
    }
  }
  const Eigen::Matrix<double, 6, 1> twist = pbvs_.Twist(bMe, bMg_);

  // Joint weights for limit avoidance (weighted least norm): a joint inside the
  // zone near a limit and still moving toward it gets a small weight. (No push
  // out of the zone: it held the arm short of goals that lie in the zone.)
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  for (int i = 0; i < n; ++i) {
    const double to_lower = q[i] - arm_.lower_limits()[i];
    const double to_upper = arm_.upper_limits()[i] - q[i];
    const double zone = config_.limit_zone_rad;
    if (zone <= 0.0) continue;
    if (to_lower < zone && last_dq_[i] <= 0.0) {
      w[i] = std::max(0.05, to_lower / zone);
    } else if (to_upper < zone && last_dq_[i] >= 0.0) {
      w[i] = std::max(0.05, to_upper / zone);
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
  Eigen::VectorXd dq = sqrt_w * solution.dq;
  out->damping = solution.damping;
  out->min_singular = solution.min_singular;

  // Far from q*, along the straight joint path to it; near it, mostly PBVS,
  // with guide_min of the joint-space law left in: it finishes what PBVS
  // cannot near a singularity (a 4-DoF arm near stretched has no joint to turn
  // its approach axis once the position is met).
  // On the way to a via point, only joint-space motion.
  const Eigen::VectorXd& q_next = has_via_ ? via_q_ : q_goal_;
  const double to_goal = (q_next - q).cwiseAbs().maxCoeff();
  const double ramp = has_via_ ? 1.0
                               : std::clamp((to_goal - config_.guide_near_rad) /
                                                (config_.guide_far_rad - config_.guide_near_rad),
                                            0.0, 1.0);
  const double guide = config_.guide_min + (1.0 - config_.guide_min) * ramp;
  // Toward a via point as fast as the limits allow (no need to stop there).
  const Eigen::VectorXd dq_joint = (q_next - q) * (has_via_ ? 1.0 / dt_s : config_.gain_per_s);
  dq = (1.0 - guide) * dq + guide * dq_joint;
  out->guide_weight = guide;
  out->q_goal_rad = has_goal_ ? q_goal_ : Eigen::VectorXd();

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

  double scale = 1.0;
  dq = Limit(q, dq, dt_s, &scale);

  // The forbidden region: shorten the step until it is allowed; failing that,
  // step along the straight joint path to q* (checked when q* was chosen)
  // instead of the blend; failing that too, hold. An arm already inside the
  // region (the other arm moved in within the margin while both stepped) may
  // take the straight-path step when the path leaves the region within one
  // check step (as PathAllowed, which skips q itself): else it could never
  // back out, and the two arms would hold each other up.
  double step = 1.0;
  if (forbidden_) {
    const auto shorten = [&](const Eigen::VectorXd& dq_try) {
      for (step = 1.0; step > 0.1; step *= 0.5) {
        if (!forbidden_(q + step * dq_try * dt_s)) return true;
      }
      return false;
    };
    const auto leaves = [&](const Eigen::VectorXd& dq_try) {
      const double length = (dq_try * dt_s).cwiseAbs().maxCoeff();
      step = 1.0;
      return length > 0.0 && forbidden_(q) &&
             !forbidden_(q + dq_try * (dt_s * config_.path_check_step_rad / length));
    };
    if (!shorten(dq)) {
      dq = Limit(q, dq_joint, dt_s, &scale);
      if (!shorten(dq) && !leaves(dq)) {
        // The path checked when q* was chosen is blocked now (the other arm
        // moved in, or a dip between the path's samples): search again after
        // unreachable_retry_s, from here, via points included.
        has_goal_ = has_via_ = making_way_ = false;
        has_failed_ = true;
        failed_bMg_ = bMg_;
        failed_at_s_ = now_s;
        return Hold(q, ServoStatus::kSafeVolume, out);
      }
    }
    dq *= step;
  }
  out->step_scale = scale * step;
  out->dq_rad_s = dq;
  out->q_target_rad = q + dq * dt_s;
  if (config_.command_lead_rad > 0.0 && last_q_target_.size() == n) {
    // The servos follow their targets with a lag and in counts: the last
    // targets' lead over the measured joints carries on (bounded, and only
    // where it is allowed), so the joints move at dq and small steps add up.
    const double r = config_.command_lead_rad;
    const Eigen::VectorXd lead = (last_q_target_ - q).cwiseMax(-r).cwiseMin(r);
    const Eigen::VectorXd carried = arm_.Clamp(out->q_target_rad + lead);
    if (!forbidden_ || !forbidden_(carried)) out->q_target_rad = carried;
  }
  last_q_target_ = out->q_target_rad;
  last_dq_ = dq;
  return ServoStatus::kMoving;
}

}  // namespace aerograsp
