#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <iostream>
#include <random>

#include "core/config.h"
#include "core/transforms.h"
#include "hardware/sim/world.h"
#include "servo/arm_servo.h"
#include "servo/ik.h"

namespace aerograsp {
namespace {

ArmModel Arm(const char* urdf) {
  return ArmModel::FromUrdfFile(std::string(AEROGRASP_DATA_DIR) + "/robots/" + urdf, "base_link",
                                "tool");
}

Eigen::VectorXd Home4() {
  Eigen::VectorXd q(4);
  q << 0.0, -0.6283185, 2.0943951, 0.0;
  return q;
}

// Steps the servo at joints q and time t while its goal search goes on (at most
// 1000 Steps); the first other status, with the Steps taken in *steps.
ServoStatus StepPastSearch(ArmServo* servo, const Eigen::VectorXd& q, double t, ServoCommand* cmd,
                           int* steps = nullptr) {
  ServoStatus status = ServoStatus::kSearching;
  int k = 0;
  while (status == ServoStatus::kSearching && k < 1000) {
    status = servo->Step(q, t, 0.01, cmd);
    ++k;
  }
  if (steps) *steps = k;
  return status;
}

// Runs the servo on an ideal arm (q integrates the command) until the target is
// reached or the step budget is spent; returns the number of steps, -1 if not reached.
int RunToTarget(const ArmModel& arm, ArmServo* servo, Eigen::VectorXd* q,
                const Eigen::Isometry3d& bMg, int max_steps, double dt = 0.01) {
  servo->SetTarget(bMg, 0.0);
  for (int k = 0; k < max_steps; ++k) {
    const double t = k * dt;
    servo->SetTarget(bMg, t);  // a fresh observation every cycle
    ServoCommand cmd;
    const ServoStatus status = servo->Step(*q, t, dt, &cmd);
    EXPECT_TRUE(status == ServoStatus::kMoving || status == ServoStatus::kSearching)
        << ServoStatusName(status);
    EXPECT_TRUE(arm.WithinLimits(cmd.q_target_rad, 1e-9));
    *q = cmd.q_target_rad;
    if (cmd.position_error_m < 1e-3 && cmd.rotation_error_rad < 1e-2) return k;
  }
  return -1;
}

class ArmServoConvergenceTest : public ::testing::TestWithParam<const char*> {};

// Targets are the FK of random joints within the limits; starts are near them
// (as a grasp after the pre-catch pose) or far (anywhere within the limits).
// The full pose counts: position 1 mm, rotation 0.01 rad.
TEST_P(ArmServoConvergenceTest, ReachesRandomReachableTargets) {
  const ArmModel arm = Arm(GetParam());
  std::mt19937 rng(11);
  int reached = 0;
  const int trials = 100;
  for (int trial = 0; trial < trials; ++trial) {
    Eigen::VectorXd q_goal(arm.dof()), q(arm.dof());
    for (int i = 0; i < arm.dof(); ++i) {
      q_goal[i] =
          std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(rng);
    }
    for (int i = 0; i < arm.dof(); ++i) {
      const double near = q_goal[i] + std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
      const double far =
          std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(rng);
      q[i] = std::clamp(trial % 2 == 0 ? near : far, arm.lower_limits()[i], arm.upper_limits()[i]);
    }
    ArmServo servo(arm, ServoConfig{});
    if (RunToTarget(arm, &servo, &q, arm.ForwardKinematics(q_goal), 1500) >= 0) ++reached;
  }
  EXPECT_GE(reached, trials * 99 / 100) << GetParam();
  std::cout << GetParam() << ": reached " << reached << " of " << trials << " targets\n";
}

INSTANTIATE_TEST_SUITE_P(Arms, ArmServoConvergenceTest,
                         ::testing::Values("arm4.urdf", "arm6.urdf"));

TEST(ArmServoTest, VelocitiesStayBoundedAtTheStretchedSingularity) {
  const ArmModel arm = Arm("arm4.urdf");
  ArmServo servo(arm, ServoConfig{});
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4);  // stretched: a singular configuration
  // A reachable target just beside the stretched arm, then one even closer to
  // stretched (elbow at 0.01 rad).
  Eigen::VectorXd q_near(4), q_nearer(4);
  q_near << 0.3, -0.05, 0.08, 0.2;
  q_nearer << 0.35, -0.01, 0.01, 0.2;
  Eigen::Isometry3d bMg = arm.ForwardKinematics(q_near);
  for (int k = 0; k < 300; ++k) {
    const double t = 0.01 * k;
    if (k == 150) bMg = arm.ForwardKinematics(q_nearer);
    servo.SetTarget(bMg, t);
    ServoCommand cmd;
    ASSERT_EQ(servo.Step(q, t, 0.01, &cmd), ServoStatus::kMoving) << k;
    ASSERT_TRUE(cmd.dq_rad_s.allFinite());
    for (int i = 0; i < 4; ++i) {
      EXPECT_LE(std::abs(cmd.dq_rad_s[i]), 0.8 * arm.velocity_limits()[i] + 1e-9);
    }
    q = cmd.q_target_rad;
  }
}

TEST(ArmServoTest, BeyondReachHoldsAsUnreachable) {
  const ArmModel arm = Arm("arm4.urdf");
  ArmServo servo(arm, ServoConfig{});
  Eigen::Isometry3d bMg = arm.ForwardKinematics(Eigen::VectorXd::Zero(4));
  bMg.translation().z() += 0.2;  // straight past the stretched arm
  servo.SetTarget(bMg, 0.0);
  ServoCommand cmd;
  EXPECT_EQ(StepPastSearch(&servo, Home4(), 0.0, &cmd), ServoStatus::kUnreachable);
  EXPECT_TRUE(cmd.dq_rad_s.isZero());
  EXPECT_EQ(cmd.q_target_rad, Home4());
}

TEST(ArmServoTest, TheSixDofArmKnowsATargetBeyondReachAtOnce) {
  // Its closed form gives every solution: none, and the search ends in the
  // Step it began, where the 4-DoF arm's goes on through random seeds.
  const ArmModel arm6 = Arm("arm6.urdf");
  ArmServo servo6(arm6, ServoConfig{});
  Eigen::Isometry3d bMg = arm6.ForwardKinematics(Eigen::VectorXd::Zero(6));
  bMg.translation().z() += 0.2;
  servo6.SetTarget(bMg, 0.0);
  ServoCommand cmd;
  int steps6 = 0;
  EXPECT_EQ(StepPastSearch(&servo6, Eigen::VectorXd::Zero(6), 0.0, &cmd, &steps6),
            ServoStatus::kUnreachable);
  EXPECT_EQ(steps6, 1);
  const ArmModel arm4 = Arm("arm4.urdf");
  ArmServo servo4(arm4, ServoConfig{});
  bMg = arm4.ForwardKinematics(Eigen::VectorXd::Zero(4));
  bMg.translation().z() += 0.2;
  servo4.SetTarget(bMg, 0.0);
  int steps4 = 0;
  EXPECT_EQ(StepPastSearch(&servo4, Home4(), 0.0, &cmd, &steps4), ServoStatus::kUnreachable);
  EXPECT_GT(steps4, 1);
}

// The joint-goal search does at most search_budget units of work per Step and
// goes on in the next ones (holding meanwhile); spread or not, it finds the
// same goal, so a mission's log does not depend on the budget's spread.
TEST(ArmServoTest, TheGoalSearchSpreadsOverStepsAndFindsTheSameGoal) {
  const ArmModel arm = Arm("arm6.urdf");
  std::mt19937 rng(5);
  const Eigen::Isometry3d bMg = arm.ForwardKinematics(DrawJointsWithinLimits(arm, &rng));
  const Eigen::VectorXd q = arm.Clamp(Eigen::VectorXd::Zero(arm.dof()));
  // A wall in j0 makes the straight path from q refused for goals beyond it:
  // the search also checks the via points' paths, sample by sample.
  const auto forbidden = [](const Eigen::VectorXd& q_try) {
    return q_try[0] > 0.3 && q_try[0] < 0.35;
  };
  Eigen::VectorXd goal[2];
  int steps[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    ServoConfig config;
    config.search_budget = k == 0 ? 5 : 1000000;
    ArmServo servo(arm, config, forbidden);
    servo.SetTarget(bMg, 0.0);
    ServoCommand cmd;
    ASSERT_EQ(StepPastSearch(&servo, q, 0.0, &cmd, &steps[k]), ServoStatus::kMoving);
    goal[k] = cmd.q_goal_rad;
  }
  EXPECT_GT(steps[0], 3);
  EXPECT_EQ(steps[1], 1);
  EXPECT_EQ(goal[0], goal[1]);
}

TEST(ArmServoTest, NeverCommandsPastAJointLimit) {
  const ArmModel arm = Arm("arm4.urdf");
  ArmServo servo(arm, ServoConfig{});
  Eigen::VectorXd q = Home4();
  // A target that pulls the elbow against its upper limit.
  Eigen::VectorXd q_far = Home4();
  q_far[2] = arm.upper_limits()[2];
  q_far[1] = arm.lower_limits()[1];
  Eigen::Isometry3d bMg = arm.ForwardKinematics(q_far);
  bMg.translation() *= 0.8;
  for (int k = 0; k < 400; ++k) {
    servo.SetTarget(bMg, 0.01 * k);
    ServoCommand cmd;
    servo.Step(q, 0.01 * k, 0.01, &cmd);
    ASSERT_TRUE(arm.WithinLimits(cmd.q_target_rad, 1e-9)) << cmd.q_target_rad.transpose();
    q = cmd.q_target_rad;
  }
}

TEST(ArmServoTest, CommandStaysContinuousAtAGraspSwitch) {
  const ArmModel arm = Arm("arm6.urdf");
  auto jump_at_switch = [&](bool declare_switch) {
    ArmServo servo(arm, ServoConfig{});
    Eigen::VectorXd q(6);
    q << 0.2, -0.8, 1.5, -0.5, 0.3, 0.1;
    Eigen::VectorXd q_a = q, q_b = q;
    q_a[0] += 0.4;
    q_b[0] -= 0.4;
    q_b[2] -= 0.3;
    Eigen::VectorXd before;
    for (int k = 0; k < 40; ++k) {
      const double t = 0.01 * k;
      const bool switching = k == 20;
      servo.SetTarget(arm.ForwardKinematics(k < 20 ? q_a : q_b), t, switching && declare_switch);
      ServoCommand cmd;
      servo.Step(q, t, 0.01, &cmd);
      if (k == 19) before = cmd.dq_rad_s;
      if (k == 20) return (cmd.dq_rad_s - before).norm();
      q = cmd.q_target_rad;
    }
    return -1.0;
  };
  // With the switch declared the command barely moves; the acceleration limit
  // alone (30 rad/s^2 * 0.01 s per joint) allows a larger jump.
  const double blended = jump_at_switch(true);
  const double unblended = jump_at_switch(false);
  EXPECT_LT(blended, 0.02);
  EXPECT_GT(unblended, 5 * blended);
}

TEST(ArmServoTest, BadInputHoldsWithZeroVelocity) {
  const ArmModel arm = Arm("arm4.urdf");
  ArmServo servo(arm, ServoConfig{});
  ServoCommand cmd;
  EXPECT_EQ(servo.Step(Home4(), 0.0, 0.01, &cmd), ServoStatus::kNoTarget);
  EXPECT_TRUE(cmd.dq_rad_s.isZero());

  Eigen::Isometry3d nan_target = arm.ForwardKinematics(Home4());
  nan_target.translation().x() = NAN;
  servo.SetTarget(nan_target, 0.0);
  EXPECT_EQ(servo.Step(Home4(), 0.0, 0.01, &cmd), ServoStatus::kInvalidTarget);
  EXPECT_TRUE(cmd.dq_rad_s.isZero());
  EXPECT_EQ(cmd.q_target_rad, Home4());

  servo.SetTarget(arm.ForwardKinematics(Eigen::VectorXd::Zero(4)), 0.0);
  EXPECT_EQ(servo.Step(Home4(), 0.5, 0.01, &cmd), ServoStatus::kStaleTarget);
  EXPECT_TRUE(cmd.dq_rad_s.isZero());

  Eigen::VectorXd q_nan = Home4();
  q_nan[1] = NAN;
  EXPECT_EQ(servo.Step(q_nan, 0.1, 0.01, &cmd), ServoStatus::kInvalidState);
  EXPECT_TRUE(cmd.dq_rad_s.isZero());
  EXPECT_TRUE(cmd.q_target_rad.allFinite());
  EXPECT_EQ(servo.Step(Eigen::VectorXd::Zero(3), 0.1, 0.01, &cmd), ServoStatus::kInvalidState);
}

TEST(ArmServoTest, ForbiddenRegionShortensOrRefusesTheStep) {
  const ArmModel arm = Arm("arm4.urdf");
  Eigen::VectorXd q = Home4();
  Eigen::VectorXd q_goal = Home4();
  q_goal[0] = 0.5;
  // The region appears in the way after the goal was chosen (as the other arm
  // moving in): beyond j0 = 0.1 nothing is allowed. Steps shorten, then hold.
  double wall_rad = 10.0;
  ArmServo servo(arm, ServoConfig{},
                 [&](const Eigen::VectorXd& q_try) { return q_try[0] > wall_rad; });
  int held = 0;
  for (int k = 0; k < 100; ++k) {
    servo.SetTarget(arm.ForwardKinematics(q_goal), 0.01 * k);
    ServoCommand cmd;
    const ServoStatus status = servo.Step(q, 0.01 * k, 0.01, &cmd);
    if (k == 0) wall_rad = 0.1;
    if (status == ServoStatus::kMoving) {
      EXPECT_LE(cmd.q_target_rad[0], k == 0 ? 10.0 : 0.1);
    } else {
      ++held;
      EXPECT_TRUE(status == ServoStatus::kSafeVolume || status == ServoStatus::kUnreachable ||
                  status == ServoStatus::kSearching)
          << ServoStatusName(status);
      EXPECT_TRUE(cmd.dq_rad_s.isZero());
      EXPECT_EQ(cmd.q_target_rad, q);
    }
    q = cmd.q_target_rad;
  }
  EXPECT_GT(q[0], 0.05);  // it got close to the wall before holding
  EXPECT_GT(held, 0);

  // Everything forbidden: no goal has an allowed path; hold from the first step.
  ArmServo refused(arm, ServoConfig{}, [](const Eigen::VectorXd&) { return true; });
  refused.SetTarget(arm.ForwardKinematics(q_goal), 0.0);
  ServoCommand cmd;
  EXPECT_EQ(StepPastSearch(&refused, Home4(), 0.0, &cmd), ServoStatus::kUnreachable);
  EXPECT_TRUE(cmd.dq_rad_s.isZero());
  EXPECT_EQ(cmd.q_target_rad, Home4());
}

// The simulated SCS servos (10-bit counts of 0.21 deg, 50 ms lag) driven for
// `seconds` toward bMg(t), a fresh target every 10 ms cycle; the largest tool
// position error over the last `settled_s`, by the true joints.
double TrackOnSimulatedServos(const ArmModel& arm, double lead_rad, double seconds,
                              double settled_s,
                              const std::function<Eigen::Isometry3d(double)>& bMg) {
  ServoConfig config;
  config.gain_per_s = 15.0;
  config.command_lead_rad = lead_rad;
  ArmServo servo(arm, config);
  SimArm sim(arm, ArmsSimConfig{}, Home4());
  double worst_m = 0.0;
  const double dt = 0.01;
  for (int k = 0; k * dt < seconds; ++k) {
    const double t = k * dt;
    servo.SetTarget(bMg(t), t);
    ServoCommand cmd;
    const ServoStatus status = servo.Step(sim.q_measured_rad(), t, dt, &cmd);
    EXPECT_TRUE(status == ServoStatus::kMoving || status == ServoStatus::kSearching)
        << ServoStatusName(status);
    sim.SetTarget(cmd.q_target_rad);
    for (int i = 0; i < 5; ++i) sim.Step(dt / 5);  // the world's 2 ms physics step
    if (t >= seconds - settled_s) {
      const double error_m =
          (arm.ForwardKinematics(sim.q_true_rad()).translation() - bMg(t + dt).translation())
              .norm();
      worst_m = std::max(worst_m, error_m);
    }
  }
  return worst_m;
}

// A step smaller than half a count rounds to the position the joint has: q +
// dq dt stalls millimetres short; with the lead the small steps add up.
TEST(ArmServoTest, TheLeadBringsQuantisedServosOntoAStillTarget) {
  const ArmModel arm = Arm("arm4.urdf");
  Eigen::VectorXd q_goal = Home4();
  q_goal[0] += 0.04;
  q_goal[1] += 0.03;
  const Eigen::Isometry3d bMg = arm.ForwardKinematics(q_goal);
  const auto still = [&](double) { return bMg; };
  const double with_lead_m = TrackOnSimulatedServos(arm, 0.03, 3.0, 0.5, still);
  const double without_m = TrackOnSimulatedServos(arm, 0.0, 3.0, 0.5, still);
  std::cout << "still target: " << 1e3 * with_lead_m << " mm with the lead, " << 1e3 * without_m
            << " mm without\n";
  EXPECT_LT(with_lead_m, 0.001);
}

// A sway of a few centimetres at 0.5 Hz (the object under a hovering vehicle): without the lead
// the joints move at a fifth of the commanded speed (a step of dq dt against
// a 50 ms lag) and the tool trails centimetres behind.
TEST(ArmServoTest, TheLeadLetsQuantisedServosFollowASway) {
  const ArmModel arm = Arm("arm4.urdf");
  // Joints swaying about home: every target is reachable.
  Eigen::VectorXd amplitude(4);
  amplitude << 0.06, 0.05, -0.05, 0.0;
  const auto sway = [&](double t) {
    return arm.ForwardKinematics(Home4() + amplitude * std::sin(2.0 * M_PI * 0.5 * t));
  };
  const double with_lead_m = TrackOnSimulatedServos(arm, 0.03, 6.0, 2.0, sway);
  const double without_m = TrackOnSimulatedServos(arm, 0.0, 6.0, 2.0, sway);
  std::cout << "swaying target: " << 1e3 * with_lead_m << " mm with the lead, " << 1e3 * without_m
            << " mm without\n";
  EXPECT_LT(with_lead_m, 0.006);
  EXPECT_LT(with_lead_m, 0.5 * without_m);
}

TEST(ServoConfigTest, DefaultsAreValidAndBadValuesNamed) {
  EXPECT_NO_THROW(ServoConfig{}.Validate("servo.yaml", "servo."));
  ServoConfig c;
  c.gain_per_s = -1;
  try {
    c.Validate("servo.yaml", "servo.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("servo.yaml: servo.gain_per_s: -1 1/s is below"));
  }
  c = ServoConfig{};
  c.orientation_weights.y() = 2.0;
  EXPECT_THROW(c.Validate("servo.yaml", "servo."), ConfigError);
  c = ServoConfig{};
  c.search_budget = 0;
  try {
    c.Validate("servo.yaml", "servo.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("servo.yaml: servo.search_budget: 0"));
  }
  c = ServoConfig{};
  c.command_lead_rad = 0.6;
  try {
    c.Validate("servo.yaml", "servo.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("servo.yaml: servo.command_lead_rad: 0.6 rad"));
  }
}

}  // namespace
}  // namespace aerograsp
