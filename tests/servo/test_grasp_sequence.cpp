#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/config.h"
#include "servo/grasp_sequence.h"

namespace aerograsp {
namespace {

ArmModel Arm6() {
  return ArmModel::FromUrdfFile(std::string(AEROGRASP_DATA_DIR) + "/robots/arm6.urdf", "base_link",
                                "tool");
}

Eigen::VectorXd Home6() {
  Eigen::VectorXd q(6);
  q << 0.0, -0.5235988, 2.0943951, -1.5707963, 0.0, 0.0;
  return q;
}

// A grasp the 6-DoF arm reaches, with its pre-catch pose reachable too.
Eigen::Isometry3d Grasp(const ArmModel& arm) {
  Eigen::VectorXd q(6);
  q << 0.3, -0.9, 1.2, 0.2, 0.6, -0.3;
  return arm.ForwardKinematics(q);
}

struct SequenceRun {
  std::vector<GraspPhase> phases;  // after each step
  std::vector<GripperCommand> gripper;
  Eigen::VectorXd q;
  double precatch_reached_s = -1.0;
  Eigen::Isometry3d bMe_at_precatch = Eigen::Isometry3d::Identity();
};

// Runs the sequence on an ideal arm for `steps` cycles of 0.01 s.
SequenceRun RunSequence(const ArmModel& arm, GraspSequence* sequence, const Eigen::Isometry3d& bMg,
                        int steps, bool fresh_targets = true) {
  SequenceRun run;
  run.q = Home6();
  sequence->Start(0.0);
  for (int k = 0; k < steps; ++k) {
    const double t = 0.01 * k;
    if (fresh_targets || k == 0) sequence->SetGrasp(bMg, t);
    GraspCommand cmd;
    const GraspPhase before = sequence->phase();
    sequence->Step(run.q, t, 0.01, &cmd);
    EXPECT_TRUE(arm.WithinLimits(cmd.joints.q_target_rad, 1e-9));
    run.q = cmd.joints.q_target_rad;
    if (before == GraspPhase::kPreCatch && cmd.phase == GraspPhase::kGrasp) {
      run.precatch_reached_s = t;
      run.bMe_at_precatch = arm.ForwardKinematics(run.q);
    }
    run.phases.push_back(cmd.phase);
    run.gripper.push_back(cmd.gripper);
  }
  return run;
}

TEST(GraspSequenceTest, PreCatchThenGraspThenClose) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequenceConfig config;
  GraspSequence sequence(&servo, config);
  const Eigen::Isometry3d bMg = Grasp(arm);
  const SequenceRun run = RunSequence(arm, &sequence, bMg, 800);
  // The phases come in order, each once.
  std::vector<GraspPhase> order;
  for (GraspPhase p : run.phases) {
    if (order.empty() || order.back() != p) order.push_back(p);
  }
  EXPECT_EQ(order, (std::vector<GraspPhase>{GraspPhase::kPreCatch, GraspPhase::kGrasp,
                                            GraspPhase::kClose, GraspPhase::kDone}));
  // The pre-catch pose is back along the grasp's approach axis z.
  const Eigen::Vector3d p_gc = bMg.inverse() * run.bMe_at_precatch.translation();
  EXPECT_NEAR(p_gc.z(), -config.precatch_distance_m, config.precatch_tolerance.position_m);
  EXPECT_NEAR(p_gc.head<2>().norm(), 0.0, config.precatch_tolerance.position_m);
  // The gripper closes only once the grasp pose is met, and stays closed.
  for (std::size_t k = 0; k < run.phases.size(); ++k) {
    const bool closing = run.phases[k] == GraspPhase::kClose || run.phases[k] == GraspPhase::kDone;
    EXPECT_EQ(run.gripper[k], closing ? GripperCommand::kClose : GripperCommand::kOpen) << k;
  }
  EXPECT_LE(ComputeApproachError(arm.ForwardKinematics(run.q), bMg).position_b.norm(),
            config.grasp_tolerance.position_m);
  // Close lasts close_time_s.
  const auto close_steps = std::count(run.phases.begin(), run.phases.end(), GraspPhase::kClose);
  EXPECT_NEAR(close_steps * 0.01, config.close_time_s, 0.015);
}

// A 6-DoF arm at home whose sequence started at t = 0 toward Grasp(arm).
struct SequenceRig {
  explicit SequenceRig(const GraspSequenceConfig& sequence_config = GraspSequenceConfig{})
      : arm(Arm6()),
        servo(arm, ServoConfig{}),
        config(sequence_config),
        sequence(&servo, config),
        bMg(Grasp(arm)),
        q(Home6()) {
    sequence.Start(0.0);
  }
  /// One 0.01 s step toward `target` (set as the grasp at t); the arm follows.
  GraspCommand Step(const Eigen::Isometry3d& target) {
    GraspCommand cmd;
    sequence.SetGrasp(target, t);
    sequence.Step(q, t, 0.01, &cmd);
    q = cmd.joints.q_target_rad;
    t += 0.01;
    return cmd;
  }
  /// Steps toward bMg until the sequence reaches `phase`, for at most 8 s.
  void StepUntil(GraspPhase phase) {
    for (int k = 0; k < 800 && sequence.phase() != phase; ++k) Step(bMg);
  }

  const ArmModel arm;
  ArmServo servo;
  const GraspSequenceConfig config;
  GraspSequence sequence;
  const Eigen::Isometry3d bMg;
  Eigen::VectorXd q;
  double t = 0.0;
};

TEST(GraspSequenceTest, AGripperThatHoldsEndsTheCloseAndTheArmKeepsStill) {
  SequenceRig rig;
  rig.StepUntil(GraspPhase::kClose);
  ASSERT_EQ(rig.sequence.phase(), GraspPhase::kClose);
  // The object's estimate moves 3 cm while the pads close; the gripper then holds.
  const Eigen::Isometry3d bMg_moved = Eigen::Translation3d(0.03, 0.0, 0.0) * rig.bMg;
  const Eigen::VectorXd q_before = rig.q;
  GraspCommand cmd = rig.Step(bMg_moved);
  EXPECT_EQ(cmd.phase, GraspPhase::kClose);
  EXPECT_GT((cmd.joints.q_target_rad - q_before).norm(), 0.0);  // still servoing while closing
  const Eigen::VectorXd q_at_hold = rig.q;
  rig.sequence.GripperHolds(rig.t);
  for (int k = 0; k < 50; ++k) {
    cmd = rig.Step(bMg_moved);
    EXPECT_EQ(cmd.phase, GraspPhase::kDone);
    EXPECT_EQ(cmd.gripper, GripperCommand::kClose);
    EXPECT_EQ(cmd.joints.q_target_rad, q_at_hold);
  }
}

TEST(GraspSequenceTest, ATargetOffTheObjectIsNotClosedOnAndTimesOut) {
  SequenceRig rig;
  rig.StepUntil(GraspPhase::kGrasp);
  ASSERT_EQ(rig.sequence.phase(), GraspPhase::kGrasp);
  rig.sequence.SetTargetOnObject(false);
  const double grasp_start_s = rig.t;
  while (rig.sequence.phase() == GraspPhase::kGrasp && rig.t < grasp_start_s + 10.0)
    EXPECT_EQ(rig.Step(rig.bMg).gripper, GripperCommand::kOpen);
  // At its target all along, never closed there, and out of time as a grasp that is not met.
  EXPECT_LE(ComputeApproachError(rig.arm.ForwardKinematics(rig.q), rig.bMg).position_b.norm(),
            rig.config.grasp_tolerance.position_m);
  EXPECT_EQ(rig.sequence.phase(), GraspPhase::kTimedOut);
  EXPECT_NEAR(rig.t - grasp_start_s, rig.config.grasp_timeout_s, 0.02);
}

TEST(GraspSequenceTest, ATargetBackOnTheObjectIsClosedOn) {
  SequenceRig rig;
  rig.sequence.SetTargetOnObject(false);
  for (int k = 0; k < 300; ++k) rig.Step(rig.bMg);  // 3 s: the grasp pose is met, held back
  EXPECT_EQ(rig.sequence.phase(), GraspPhase::kGrasp);
  rig.sequence.SetTargetOnObject(true);
  const GraspCommand cmd = rig.Step(rig.bMg);
  EXPECT_EQ(cmd.phase, GraspPhase::kClose);
  EXPECT_EQ(cmd.gripper, GripperCommand::kClose);
}

TEST(GraspSequenceTest, HeldAtTheGraspPoseItDoesNotCloseUntilReleased) {
  SequenceRig rig;
  rig.StepUntil(GraspPhase::kGrasp);
  rig.sequence.HoldAtGrasp(true);
  for (int k = 0; k < 200; ++k)  // 2 s: the grasp pose is met, held there open
    EXPECT_EQ(rig.Step(rig.bMg).gripper, GripperCommand::kOpen);
  EXPECT_EQ(rig.sequence.phase(), GraspPhase::kGrasp);
  EXPECT_TRUE(rig.sequence.at_grasp());
  rig.sequence.HoldAtGrasp(false);
  const GraspCommand cmd = rig.Step(rig.bMg);
  EXPECT_EQ(cmd.phase, GraspPhase::kClose);
  EXPECT_FALSE(rig.sequence.at_grasp());
}

TEST(GraspSequenceTest, HeldAtTheGraspPoseItTimesOutOnItsPhaseClock) {
  SequenceRig rig;
  rig.StepUntil(GraspPhase::kGrasp);
  rig.sequence.HoldAtGrasp(true);
  const double grasp_start_s = rig.t;
  while (rig.sequence.phase() == GraspPhase::kGrasp && rig.t < grasp_start_s + 10.0)
    rig.Step(rig.bMg);
  EXPECT_EQ(rig.sequence.phase(), GraspPhase::kTimedOut);
  EXPECT_NEAR(rig.t - grasp_start_s, rig.config.grasp_timeout_s, 0.02);
}

TEST(GraspSequenceTest, GripperHoldsOutsideTheCloseChangesNothing) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequence sequence(&servo, GraspSequenceConfig{});
  sequence.Start(0.0);
  sequence.SetGrasp(Grasp(arm), 0.0);
  sequence.GripperHolds(0.0);
  EXPECT_EQ(sequence.phase(), GraspPhase::kPreCatch);
  GraspCommand cmd;
  sequence.Step(Home6(), 0.0, 0.01, &cmd);
  EXPECT_EQ(cmd.gripper, GripperCommand::kOpen);
}

TEST(GraspSequenceTest, UnreachableGraspTimesOutAndHolds) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequenceConfig config;
  config.precatch_timeout_s = 0.5;
  GraspSequence sequence(&servo, config);
  Eigen::Isometry3d beyond = Grasp(arm);
  beyond.translation() *= 3.0;  // out of reach
  const SequenceRun run = RunSequence(arm, &sequence, beyond, 100);
  EXPECT_EQ(run.phases.back(), GraspPhase::kTimedOut);
  const auto timed_out_at =
      std::find(run.phases.begin(), run.phases.end(), GraspPhase::kTimedOut) - run.phases.begin();
  EXPECT_NEAR(timed_out_at * 0.01, config.precatch_timeout_s, 0.015);
  EXPECT_EQ(run.gripper.back(), GripperCommand::kOpen);
  EXPECT_EQ(run.q, Home6());  // never moved
}

TEST(GraspSequenceTest, StaleGraspHoldsAndTimesOutInTheGraspPhase) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequenceConfig config;
  config.precatch_timeout_s = 100.0;
  config.grasp_timeout_s = 1.0;
  GraspSequence sequence(&servo, config);
  // One observation only: after stale_target_s (0.2 s) the servo holds.
  const SequenceRun run = RunSequence(arm, &sequence, Grasp(arm), 300, /*fresh_targets=*/false);
  EXPECT_EQ(run.phases.back(), GraspPhase::kPreCatch);  // held, still waiting
  EXPECT_EQ(run.gripper.back(), GripperCommand::kOpen);
  // With a short pre-catch timeout the same stale target ends in a timeout.
  config.precatch_timeout_s = 1.0;
  GraspSequence short_sequence(&servo, config);
  const SequenceRun timed_out = RunSequence(arm, &short_sequence, Grasp(arm), 300, false);
  EXPECT_EQ(timed_out.phases.back(), GraspPhase::kTimedOut);
}

TEST(GraspSequenceTest, SwitchDuringTheGraspPhaseGoesBackToPreCatch) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequence sequence(&servo, GraspSequenceConfig{});
  const Eigen::Isometry3d bMg = Grasp(arm);
  Eigen::VectorXd q = Home6();
  sequence.Start(0.0);
  GraspCommand cmd;
  int k = 0;
  for (; k < 800 && sequence.phase() != GraspPhase::kGrasp; ++k) {
    sequence.SetGrasp(bMg, 0.01 * k);
    sequence.Step(q, 0.01 * k, 0.01, &cmd);
    q = cmd.joints.q_target_rad;
  }
  ASSERT_EQ(sequence.phase(), GraspPhase::kGrasp);
  Eigen::VectorXd q_other(6);
  q_other << -0.3, -0.9, 1.2, -0.2, 0.6, 0.3;
  sequence.SetGrasp(arm.ForwardKinematics(q_other), 0.01 * k, /*is_switch=*/true);
  EXPECT_EQ(sequence.Step(q, 0.01 * k, 0.01, &cmd), GraspPhase::kPreCatch);
  EXPECT_EQ(cmd.gripper, GripperCommand::kOpen);
}

TEST(GraspSequenceTest, HeldAtThePreCatchPoseUntilReleasedWithoutTimingOut) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequenceConfig config;
  config.precatch_timeout_s = 2.0;
  GraspSequence sequence(&servo, config);
  const Eigen::Isometry3d bMg = Grasp(arm);
  Eigen::VectorXd q = Home6();
  sequence.Start(0.0);
  sequence.HoldAtPreCatch(true);
  GraspCommand cmd;
  bool reached = false;
  // 5 s held: longer than the pre-catch timeout, yet neither moving in nor timing out.
  for (int k = 0; k < 500; ++k) {
    sequence.SetGrasp(bMg, 0.01 * k);
    sequence.Step(q, 0.01 * k, 0.01, &cmd);
    q = cmd.joints.q_target_rad;
    reached = reached || sequence.at_precatch();
    ASSERT_EQ(cmd.phase, GraspPhase::kPreCatch) << k;
  }
  EXPECT_TRUE(reached);
  EXPECT_TRUE(sequence.at_precatch());
  sequence.HoldAtPreCatch(false);
  sequence.SetGrasp(bMg, 5.0);
  sequence.Step(q, 5.0, 0.01, &cmd);
  EXPECT_EQ(cmd.phase, GraspPhase::kGrasp);
  EXPECT_FALSE(sequence.at_precatch());
}

TEST(GraspSequenceTest, AGivenPreCatchPoseIsTheOneServoedTo) {
  const ArmModel arm = Arm6();
  ArmServo servo(arm, ServoConfig{});
  GraspSequenceConfig config;
  GraspSequence sequence(&servo, config);
  const Eigen::Isometry3d bMg = Grasp(arm);
  // A pre-catch pose 5 cm to the side of the default one.
  const Eigen::Isometry3d bMp = Eigen::Translation3d(0.0, 0.05, 0.0) * sequence.PreCatchPose(bMg);
  Eigen::VectorXd q = Home6();
  sequence.Start(0.0);
  sequence.HoldAtPreCatch(true);
  GraspCommand cmd;
  for (int k = 0; k < 500; ++k) {
    sequence.SetGrasp(bMg, bMp, 0.01 * k);
    sequence.Step(q, 0.01 * k, 0.01, &cmd);
    q = cmd.joints.q_target_rad;
  }
  ASSERT_TRUE(sequence.at_precatch());
  EXPECT_LE((arm.ForwardKinematics(q).translation() - bMp.translation()).norm(),
            config.precatch_tolerance.position_m);
}

TEST(GraspSequenceConfigTest, DefaultsAreValidAndBadValuesNamed) {
  EXPECT_NO_THROW(GraspSequenceConfig{}.Validate("servo.yaml", "grasp_sequence."));
  GraspSequenceConfig c;
  c.grasp_timeout_s = 0.0;
  try {
    c.Validate("servo.yaml", "grasp_sequence.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("servo.yaml: grasp_sequence.grasp_timeout_s"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace aerograsp
