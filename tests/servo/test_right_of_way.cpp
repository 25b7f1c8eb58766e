#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "core/collision.h"
#include "core/platform.h"
#include "servo/arm_servo.h"
#include "servo/collision_predicate.h"
#include "servo/right_of_way.h"

namespace aerograsp {
namespace {

TEST(RightOfWayTest, OnlyTheArmFartherFromItsTargetMakesWayWhenBothAreHeld) {
  RightOfWay row;
  const double fresh_s = 0.2;
  EXPECT_FALSE(row.ShouldYield(0, 0.0, 0.3, fresh_s));  // nothing posted by the other arm
  row.Post(1, 0.0, /*held=*/false, 0.1);
  EXPECT_FALSE(row.ShouldYield(0, 0.0, 0.3, fresh_s));  // the other arm is moving: wait
  row.Post(1, 0.0, /*held=*/true, 0.1);
  EXPECT_TRUE(row.ShouldYield(0, 0.01, 0.3, fresh_s));    // both held, seat 0 is farther
  EXPECT_FALSE(row.ShouldYield(0, 0.01, 0.05, fresh_s));  // both held, seat 0 is nearer
  EXPECT_FALSE(row.ShouldYield(0, 0.5, 0.3, fresh_s));    // the other arm's post is stale
  row.Post(0, 0.0, /*held=*/true, 0.1);
  EXPECT_TRUE(row.ShouldYield(1, 0.0, 0.1, fresh_s));  // a tie: seat 1 makes way
  EXPECT_FALSE(row.ShouldYield(0, 0.0, 0.1, fresh_s));
}

struct DualRun {
  bool reached[2] = {false, false};
  int contacts = 0;  ///< steps after which the arms touch or an arm is in the safe volume
};

// Both arms servo at once from `start` to the FK of `goal` (an ideal arm
// follows its targets), each servo forbidden the safe volume and the other arm.
DualRun RunBothArms(const Platform& platform, const PlatformCollision& collision,
                    const Eigen::VectorXd (&start)[2], const Eigen::VectorXd (&goal)[2],
                    RightOfWay* right_of_way) {
  Eigen::VectorXd q[2] = {start[0], start[1]};
  std::unique_ptr<ArmServo> servo[2];
  Eigen::Isometry3d bMg[2];
  for (int a = 0; a < 2; ++a) {
    const ArmModel& arm = platform.arm(kSides[a]);
    ServoConfig config;
    config.via_rad = {arm.Clamp(Eigen::VectorXd::Zero(arm.dof())), platform.home(kSides[a])};
    servo[a] = std::make_unique<ArmServo>(
        arm, config, MakeCollisionPredicate(collision, kSides[a], 0.005, &q[1 - a]), right_of_way,
        a);
    bMg[a] = arm.ForwardKinematics(goal[a]);
  }
  const PoseTolerance tolerance;  // 1 mm, 0.01 rad approach, 0.02 rad roll
  DualRun run;
  const double dt_s = 0.01;
  for (int k = 0; k < 800 && !(run.reached[0] && run.reached[1]); ++k) {
    ServoCommand cmd[2];
    for (int a = 0; a < 2; ++a) {
      servo[a]->SetTarget(bMg[a], k * dt_s);
      servo[a]->Step(q[a], k * dt_s, dt_s, &cmd[a]);
    }
    for (int a = 0; a < 2; ++a) {
      q[a] = cmd[a].q_target_rad;
      run.reached[a] = run.reached[a] || tolerance.Met(cmd[a].error);
    }
    if (collision.ArmsCollide(q[0], q[1]) || collision.ArmInSafeVolume(Side::kLeft, q[0]) ||
        collision.ArmInSafeVolume(Side::kRight, q[1])) {
      ++run.contacts;
    }
  }
  return run;
}

// Both 4-DoF arms swing across the middle at once (start and goal drawn at
// random, each pair jointly collision-free): each arm's straight joint path
// passes through the other arm, whether that stands at its start or its goal. The servos, each
// holding the other's current joints forbidden, used to stop mid-way and hold each other up for
// good. With a shared right of way the arm farther from its target backs off and both arrive, never
// touching.
TEST(RightOfWayTest, TwoArmsWhosePathsCrossBothArriveWithoutTouching) {
  const Platform platform =
      Platform::Load(std::string(AEROGRASP_DATA_DIR) + "/config/platform_4dof.yaml");
  const PlatformCollision collision(platform);
  Eigen::VectorXd start[2] = {Eigen::VectorXd(4), Eigen::VectorXd(4)};
  Eigen::VectorXd goal[2] = {Eigen::VectorXd(4), Eigen::VectorXd(4)};
  start[0] << -1.03, -1.02, 0.21, 0.96;
  start[1] << 1.52, -0.82, -0.10, -1.78;
  goal[0] << 0.86, -0.50, 2.01, 0.63;
  goal[1] << 0.59, -0.78, 1.45, 1.62;
  ASSERT_FALSE(collision.ArmsCollide(start[0], start[1], 0.005));
  ASSERT_FALSE(collision.ArmsCollide(goal[0], goal[1], 0.005));
  // Each arm's straight path passes through the other arm, standing at its start or goal.
  const auto path_hits = [&](int a, const Eigen::VectorXd& q_other) {
    for (double s = 0.0; s <= 1.0; s += 0.01) {
      const Eigen::VectorXd q = start[a] + s * (goal[a] - start[a]);
      if (a == 0 ? collision.ArmsCollide(q, q_other) : collision.ArmsCollide(q_other, q))
        return true;
    }
    return false;
  };
  ASSERT_TRUE(path_hits(0, start[1]) && path_hits(0, goal[1]));
  ASSERT_TRUE(path_hits(1, start[0]) && path_hits(1, goal[0]));

  RightOfWay right_of_way;
  const DualRun shared = RunBothArms(platform, collision, start, goal, &right_of_way);
  EXPECT_TRUE(shared.reached[0]);
  EXPECT_TRUE(shared.reached[1]);
  EXPECT_EQ(shared.contacts, 0);

  // Without the right of way they hold each other up (and still never touch).
  const DualRun alone = RunBothArms(platform, collision, start, goal, nullptr);
  EXPECT_FALSE(alone.reached[0] && alone.reached[1]);
  EXPECT_EQ(alone.contacts, 0);
}

}  // namespace
}  // namespace aerograsp
