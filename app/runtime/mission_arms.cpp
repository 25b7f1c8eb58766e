#include "app/runtime/mission_arms.h"

#include <fmt/format.h>

#include <limits>

#include "app/runtime/mission_evaluator.h"
#include "core/collision.h"
#include "servo/collision_predicate.h"

namespace aerograsp {
ArmController MakeArmController(const MissionConfig& config, const Platform& platform, Side side,
                                const PlatformCollision& collision,
                                const Eigen::VectorXd* q_other_rad, double precatch_distance_m) {
  const ArmModel& arm = platform.arm(side);
  ServoConfig servo_config = config.ServoFor(arm.dof());
  servo_config.via_rad = {arm.Clamp(Eigen::VectorXd::Zero(arm.dof())), platform.home(side)};
  ArmController c;
  c.servo = std::make_unique<ArmServo>(
      arm, servo_config,
      MakeCollisionPredicate(collision, side, config.servo_margin_m, q_other_rad));
  GraspSequenceConfig sequence_config = config.grasp_sequence;
  sequence_config.precatch_distance_m = precatch_distance_m;
  sequence_config.close_time_s = platform.config().gripper.close_time_s;
  c.sequence = std::make_unique<GraspSequence>(c.servo.get(), sequence_config);
  return c;
}

GraspArms::GraspArms(const Platform& platform, const GraspPlanner& planner,
                     const PlatformCollision& collision, const MissionConfig& config,
                     const Eigen::VectorXd* q, MissionEvaluator* evaluator,
                     std::function<void(const std::string&)> log)
    : platform_(platform),
      planner_(planner),
      policy_(config.policy),
      q_(q),
      evaluator_(evaluator),
      log_(std::move(log)),
      ik_{ArmIk(platform.arm(Side::kLeft)), ArmIk(platform.arm(Side::kRight))} {
  for (int a = 0; a < 2; ++a) {
    ArmController c = MakeArmController(config, platform, kSides[a], collision, &q_[1 - a],
                                        config.planner.precatch_distance_m);
    servo_[a] = std::move(c.servo);
    sequence_[a] = std::move(c.sequence);
  }
}

void GraspArms::SetGrasps(const DualGrasp& grasp, const Eigen::Isometry3d& dMo, double t_s) {
  has_reached_[0] = has_reached_[1] = false;
  anchored_[0] = anchored_[1] = false;
  // The tool frame the planner's joints reach, not the contact frame g: the
  // gripper is symmetric, so the planner may take g turned half a turn about
  // its approach axis, which a 4-DoF arm cannot reach as such.
  const ArmGrasp* arm_grasps[2] = {&grasp.left, &grasp.right};
  const Eigen::Isometry3d oMd = dMo.inverse();
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    const Eigen::Isometry3d oMb = oMd * platform_.dMb(side);
    oMg_[a] = oMb * platform_.arm(side).ForwardKinematics(arm_grasps[a]->q_grasp);
    oMp_[a] = oMb * platform_.arm(side).ForwardKinematics(arm_grasps[a]->q_precatch);
    reached_q_grasp_[a] = arm_grasps[a]->q_grasp;
    reached_q_precatch_[a] = arm_grasps[a]->q_precatch;
    reached_stamp_s_[a] = t_s;
    servo_[a]->SetSeedHints({arm_grasps[a]->q_precatch, arm_grasps[a]->q_grasp});
  }
}

void GraspArms::Start(const DualGrasp& grasp, const Eigen::Isometry3d& dMo, double t_s) {
  SetGrasps(grasp, dMo, t_s);
  for (int a = 0; a < 2; ++a) {
    sequence_[a]->Start(t_s);
    sequence_[a]->HoldAtPreCatch(true);
    switch_pending_[a] = false;
  }
}

void GraspArms::Switch(const DualGrasp& grasp, const Eigen::Isometry3d& dMo,
                       const SwitchState& before, double t_s) {
  SetGrasps(grasp, dMo, t_s);
  switch_pending_[0] = grasp.left.pair != before.left_pair;
  switch_pending_[1] = grasp.right.pair != before.right_pair;
  for (auto& sequence : sequence_) sequence->HoldAtPreCatch(true);
}

void GraspArms::Aim(int a, const ArmGrasp& g, double t_s) {
  const ArmModel& arm = platform_.arm(kSides[a]);
  reached_q_grasp_[a] = g.q_grasp;
  reached_q_precatch_[a] = g.q_precatch;
  reached_stamp_s_[a] = t_s;
  reached_bMg_[a] = arm.ForwardKinematics(g.q_grasp);
  reached_bMp_[a] = arm.ForwardKinematics(g.q_precatch);
  has_reached_[a] = true;
  anchored_[a] = false;  // in the object frame at the next cycle
  servo_[a]->SetSeedHints({g.q_precatch, g.q_grasp});
  sequence_[a]->Start(t_s);
  sequence_[a]->HoldAtPreCatch(false);
  unreachable_since_s_[a] = -1.0;
}

void GraspArms::GoIn() {
  for (auto& sequence : sequence_) sequence->HoldAtPreCatch(false);
}

void GraspArms::SeedHome() {
  for (int a = 0; a < 2; ++a) servo_[a]->SetSeedHints({platform_.home(kSides[a])});
}

void GraspArms::Hold(ArmsDriver* driver) {
  for (int a = 0; a < 2; ++a) {
    servo_[a]->Reset();
    driver->SetJointTargets(kSides[a], q_[a]);
  }
}

bool GraspArms::SolveFollowed(int a, int pair, const Eigen::Isometry3d& dMo, double t_s) {
  Infeasibility why = Infeasibility::kNone;
  // Seeded with the last accepted grasp joints, not the measured ones: the
  // solution nearest them is the followed branch (the 6-DoF arm's sampled
  // approaches lie 0.1-0.4 rad apart, and one nearer the arm on its way in
  // would be refused by the branch gate below).
  if (!planner_.EvaluateArm(kSides[a], pair, dMo, reached_q_grasp_[a], &solved_[a], &why))
    return false;
  if (!OnFollowedBranch(solved_[a].q_grasp, reached_q_grasp_[a], t_s - reached_stamp_s_[a],
                        policy_)) {
    return false;
  }
  reached_q_grasp_[a] = solved_[a].q_grasp;
  reached_q_precatch_[a] = solved_[a].q_precatch;
  reached_stamp_s_[a] = t_s;
  return true;
}

namespace {

// Joints of the arm that reach bMe, or its position with the rotation about
// it nearest bMe's (a 4-DoF arm's approach follows from its position), the
// solution nearest q_seed; false when the position is out of reach.
bool ReachNearest(const ArmIk& ik, const Eigen::Isometry3d& bMe, const Eigen::VectorXd& q_seed,
                  Eigen::VectorXd* q) {
  std::vector<Eigen::VectorXd> solutions;
  if ((ik.closed_form_solves_pose() && ik.SolvePose(bMe, q_seed, &solutions) > 0) ||
      ik.SolvePosition(bMe.translation(), bMe.linear().col(0), q_seed, &solutions) > 0) {
    *q = solutions.front();
    return true;
  }
  return false;
}

}  // namespace

bool GraspArms::CarryWithObject(int a, const Eigen::Isometry3d& bMo, double t_s) {
  Eigen::VectorXd q_grasp, q_precatch;
  if (!ReachNearest(ik_[a], bMo * anchor_oMg_[a], reached_q_grasp_[a], &q_grasp) ||
      !ReachNearest(ik_[a], bMo * anchor_oMp_[a], reached_q_precatch_[a], &q_precatch) ||
      !OnFollowedBranch(q_grasp, reached_q_grasp_[a], t_s - reached_stamp_s_[a], policy_)) {
    return false;
  }
  const ArmModel& arm = platform_.arm(kSides[a]);
  reached_bMg_[a] = arm.ForwardKinematics(q_grasp);
  reached_bMp_[a] = arm.ForwardKinematics(q_precatch);
  reached_q_grasp_[a] = q_grasp;
  reached_q_precatch_[a] = q_precatch;
  reached_stamp_s_[a] = t_s;
  return true;
}

std::optional<std::string> GraspArms::Step(double t, double dt_s, const FollowView& view,
                                           const SwitchState& followed, ArmsDriver* driver) {
  const int pairs[2] = {followed.left_pair, followed.right_pair};
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    const Eigen::Isometry3d bMo = platform_.dMb(side).inverse() * view.dMo;
    // The followed pair solved again for the object where it is now (the
    // planner's closed-form grasp-axis IK): targets the arm reaches exactly,
    // and their joints as the servo's IK seeds. When it is out of reach for
    // this instant (or on another IK branch), the last exact targets move on
    // with the object as far as the arm reaches them (and re-evaluation
    // decides whether to switch); failing that too, the last targets stand.
    if (pairs[a] >= 0 && SolveFollowed(a, pairs[a], view.dMo, t)) {
      const ArmModel& arm = platform_.arm(side);
      const ArmGrasp& now = solved_[a];
      servo_[a]->SetSeedHints({now.q_precatch, now.q_grasp});
      reached_bMg_[a] = arm.ForwardKinematics(now.q_grasp);
      reached_bMp_[a] = arm.ForwardKinematics(now.q_precatch);
      has_reached_[a] = true;
      anchored_[a] = false;
    } else if (!has_reached_[a]) {
      reached_bMg_[a] = bMo * oMg_[a];
      reached_bMp_[a] = bMo * oMp_[a];
    } else if (anchored_[a]) {
      CarryWithObject(a, bMo, t);
    }
    if (has_reached_[a] && !anchored_[a]) {
      anchor_oMg_[a] = bMo.inverse() * reached_bMg_[a];
      anchor_oMp_[a] = bMo.inverse() * reached_bMp_[a];
      anchored_[a] = true;
    }
    // The anchor is the followed grasp on the object as last solved exactly.
    const Eigen::Vector3d grasp_b = (bMo * anchor_oMg_[a]).translation();
    const bool on_object =
        !anchored_[a] || TargetOnObject(reached_bMg_[a].translation(), grasp_b, policy_);
    if (!on_object && sequence_[a]->target_on_object() &&
        sequence_[a]->phase() == GraspPhase::kGrasp) {
      log_(
          fmt::format("servo   {} arm: its target is {:.1f} mm off its grasp on the object (out of "
                      "reach for {:.0f} ms): not closing there",
                      kArmNames[a], 1e3 * (reached_bMg_[a].translation() - grasp_b).norm(),
                      1e3 * (t - reached_stamp_s_[a])));
    }
    sequence_[a]->SetTargetOnObject(on_object);
    // At its grasp pose the arm closes right after the other (MayClose).
    if (!sequence_[a]->at_grasp()) {
      at_grasp_since_s_[a] = -1.0;
    } else if (at_grasp_since_s_[a] < 0) {
      at_grasp_since_s_[a] = t;
    }
    const double waited_s = at_grasp_since_s_[a] < 0 ? 0.0 : t - at_grasp_since_s_[a];
    // An other arm whose target stands off the object (the gate holds it) is
    // not near its grasp, however near that target it is.
    const int b = 1 - a;
    const double other_error_m =
        sequence_[b]->target_on_object() ? error_m_[b] : std::numeric_limits<double>::infinity();
    sequence_[a]->HoldAtGrasp(!MayClose(sequence_[b]->phase(), other_error_m, waited_s, policy_));
    sequence_[a]->SetGrasp(reached_bMg_[a], reached_bMp_[a], view.stamp_s, switch_pending_[a]);
    switch_pending_[a] = false;
    GraspCommand command;
    const GraspPhase phase_before = sequence_[a]->phase();
    if (view.holds[a]) sequence_[a]->GripperHolds(t);
    sequence_[a]->Step(q_[a], t, dt_s, &command);
    if (evaluator_ && phase_before != GraspPhase::kClose && command.phase == GraspPhase::kClose) {
      ClosingView closing;
      closing.dMo_estimate = view.dMo;
      closing.dMe = platform_.dMb(side) * platform_.arm(side).ForwardKinematics(q_[a]);
      closing.bMg_target = reached_bMg_[a];
      closing.object_held_in_world = view.object_held_in_world;
      closing.target_age_s = t - reached_stamp_s_[a];
      if (pairs[a] >= 0) closing.pair_width_m = planner_.contacts().pairs[pairs[a]].width_m();
      evaluator_->Closing(a, closing);
    }
    if (evaluator_ && phase_before == GraspPhase::kClose && command.phase == GraspPhase::kDone)
      evaluator_->Closed(a);
    error_m_[a] = command.joints.position_error_m;
    if (command.servo_status != last_status_[a]) {
      log_(fmt::format("servo   {} arm: {} (phase {}, {:.1f} mm from the target)", kArmNames[a],
                       ServoStatusName(command.servo_status), GraspPhaseName(command.phase),
                       1e3 * command.joints.position_error_m));
      last_status_[a] = command.servo_status;
    }
    const bool no_way = command.servo_status == ServoStatus::kUnreachable ||
                        command.servo_status == ServoStatus::kSearching;
    if (!no_way) {
      unreachable_since_s_[a] = -1.0;
    } else if (unreachable_since_s_[a] < 0) {
      unreachable_since_s_[a] = t;
    }
    if (command.servo_status == ServoStatus::kInvalidState)
      return fmt::format("{} arm: invalid joint readings", kArmNames[a]);
    driver->SetJointTargets(side, command.joints.q_target_rad);
    driver->SetGripper(side, command.gripper);
  }
  return std::nullopt;
}

bool GraspArms::Retract(double t, double dt_s, ArmsDriver* driver,
                        std::optional<std::string>* emergency) {
  bool home = true;
  for (int a = 0; a < 2; ++a) {
    const Side side = kSides[a];
    const ArmModel& arm = platform_.arm(side);
    servo_[a]->SetTarget(arm.ForwardKinematics(platform_.home(side)), t);
    ServoCommand command;
    const ServoStatus status = servo_[a]->Step(q_[a], t, dt_s, &command);
    if (status == ServoStatus::kInvalidState) {
      *emergency = fmt::format("{} arm: invalid joint readings", kArmNames[a]);
      return false;
    }
    driver->SetJointTargets(side, command.q_target_rad);
    home = home && command.position_error_m < policy_.home_tolerance_m;
  }
  return home;
}

}  // namespace aerograsp
