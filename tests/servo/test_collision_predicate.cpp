#include <gtest/gtest.h>

#include <random>

#include "servo/collision_predicate.h"

namespace aerograsp {
namespace {

Platform Load4Dof() {
  return Platform::Load(std::string(AEROGRASP_DATA_DIR) + "/config/platform_4dof.yaml");
}

// Upper arm raised past horizontal: inside the safe volume above the shoulders.
Eigen::VectorXd RaisedArm() {
  Eigen::VectorXd q(4);
  q << 0.0, -1.74, 0.0, 0.0;
  return q;
}

TEST(CollisionPredicateTest, ForbidsTheSafeVolumeTheOtherArmAndBadJoints) {
  const Platform platform = Load4Dof();
  const PlatformCollision collision(platform);
  ASSERT_TRUE(collision.ArmInSafeVolume(Side::kLeft, RaisedArm()));
  Eigen::VectorXd q_right = platform.home(Side::kRight);
  const ForbiddenPredicate left = MakeCollisionPredicate(collision, Side::kLeft, 0.005, &q_right);
  EXPECT_FALSE(left(platform.home(Side::kLeft)));
  EXPECT_TRUE(left(RaisedArm()));
  Eigen::VectorXd q_nan = platform.home(Side::kLeft);
  q_nan[2] = NAN;
  EXPECT_TRUE(left(q_nan));
  EXPECT_TRUE(left(Eigen::VectorXd::Zero(3)));  // wrong size: forbidden, no throw
  // Both arms yawed toward each other, reaching across: they touch.
  Eigen::VectorXd q_left(4);
  q_left << -1.5708, -1.2, 0.3, 0.0;
  q_right << 1.5708, -1.2, 0.3, 0.0;
  ASSERT_TRUE(collision.ArmsCollide(q_left, q_right));
  EXPECT_TRUE(left(q_left));
  // Without the other arm only the safe volume counts.
  EXPECT_EQ(MakeCollisionPredicate(collision, Side::kLeft, 0.005)(q_left),
            collision.ArmInSafeVolume(Side::kLeft, q_left, 0.005));
  EXPECT_THROW(MakeCollisionPredicate(collision, Side::kLeft, -0.01), std::invalid_argument);
}

// Targets anywhere (also inside the safe volume), random starts outside it: no
// commanded joint target ever puts the arm into the volume. Without the
// predicate the same runs do enter it, so the check can fail.
TEST(CollisionPredicateTest, ServoNeverEntersTheSafeVolume) {
  const Platform platform = Load4Dof();
  const PlatformCollision collision(platform);
  const ArmModel& arm = platform.arm(Side::kLeft);
  auto entries_in_runs = [&](bool with_predicate) {
    std::mt19937 rng(5);
    auto random_q = [&] {
      Eigen::VectorXd q(arm.dof());
      for (int i = 0; i < arm.dof(); ++i) {
        q[i] = std::uniform_real_distribution<double>(arm.lower_limits()[i],
                                                      arm.upper_limits()[i])(rng);
      }
      return q;
    };
    int entries = 0;
    for (int trial = 0; trial < 40; ++trial) {
      Eigen::VectorXd q = random_q();
      while (collision.ArmInSafeVolume(Side::kLeft, q, 0.005)) q = random_q();
      // Every other target is inside the volume.
      Eigen::VectorXd q_goal = trial % 2 == 0 ? RaisedArm() : random_q();
      q_goal[0] = random_q()[0];
      ArmServo servo(arm, ServoConfig{},
                     with_predicate ? MakeCollisionPredicate(collision, Side::kLeft, 0.005)
                                    : ForbiddenPredicate{});
      for (int k = 0; k < 200; ++k) {
        servo.SetTarget(arm.ForwardKinematics(q_goal), 0.01 * k);
        ServoCommand cmd;
        servo.Step(q, 0.01 * k, 0.01, &cmd);
        q = cmd.q_target_rad;
        if (collision.ArmInSafeVolume(Side::kLeft, q)) ++entries;
      }
    }
    return entries;
  };
  EXPECT_EQ(entries_in_runs(true), 0);
  EXPECT_GT(entries_in_runs(false), 0);
}

}  // namespace
}  // namespace aerograsp
