// The arms' guard on their joint readings: readings the servos cannot act on
// (a NaN, or fewer joints than the arm has) send no command to the driver and
// name the arm, which the mission takes as its emergency. No device produces
// such readings (the bus gives whole counts, the simulator finite joints), so
// they are given here to the arms' step directly, over the in-process arms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/runtime/mission_arms.h"
#include "app/runtime/mission_config.h"
#include "core/collision.h"
#include "core/data_dir.h"
#include "grasp/planner.h"
#include "hardware/hardware_config.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {

class GraspArmsTest : public ::testing::Test {
 protected:
  GraspArmsTest()
      : config_(MissionConfig::Load(DataPath("config/mission_default.yaml"))),
        devices_(Hardware::Open(
            HardwareConfig::InProcessSimulation(DataPath("config/platform_4dof.yaml"),
                                                DataPath("config/world_default.yaml")),
            1)),
        planner_(devices_->platform(), Box(), ContactSet{}, config_.planner),
        collision_(devices_->platform()),
        arms_(devices_->platform(), planner_, collision_, config_, q_, nullptr,
              [this](const std::string& line) { log_.push_back(line); }) {
    for (int a = 0; a < 2; ++a) q_[a] = devices_->arms().JointPositions(kSides[a]);
  }
  static GraspObject Box() {
    GraspObject o;
    o.name = "box";
    o.mesh_o = test::BoxMesh(Eigen::Vector3d(0.05, 0.05, 0.05));
    o.mass_kg = 0.3;
    return o;
  }
  /// The world arm's target set to `q` through the driver: a command the
  /// arms' step must not replace when it refuses the readings.
  Eigen::VectorXd Sentinel(Side side) {
    const Eigen::VectorXd q =
        devices_->platform().home(side) + Eigen::VectorXd::Constant(q_[0].size(), 0.1);
    devices_->arms().SetJointTargets(side, q);
    return target(side);  // as the world arm took it (within its limits)
  }
  const Eigen::VectorXd& target(Side side) { return devices_->world()->arm(side).target_rad(); }

  MissionConfig config_;
  std::unique_ptr<Hardware> devices_;
  GraspPlanner planner_;
  PlatformCollision collision_;
  Eigen::VectorXd q_[2];
  std::vector<std::string> log_;
  GraspArms arms_;
};

TEST_F(GraspArmsTest, HealthyReadingsAreServoedOn) {
  const Eigen::VectorXd sentinel = Sentinel(Side::kLeft);
  std::optional<std::string> emergency;
  arms_.Retract(0.0, 0.01, &devices_->arms(), &emergency);
  EXPECT_FALSE(emergency.has_value());
  EXPECT_FALSE(target(Side::kLeft).isApprox(sentinel));  // a command went out
}

TEST_F(GraspArmsTest, ANanJointReadingSendsNoCommandAndNamesTheArm) {
  const Eigen::VectorXd sentinel = Sentinel(Side::kLeft);
  q_[0][1] = std::nan("");
  std::optional<std::string> emergency;
  EXPECT_FALSE(arms_.Retract(0.0, 0.01, &devices_->arms(), &emergency));
  ASSERT_TRUE(emergency.has_value());
  EXPECT_EQ(*emergency, "left arm: invalid joint readings");
  EXPECT_TRUE(target(Side::kLeft).isApprox(sentinel));
}

TEST_F(GraspArmsTest, ReadingsOfTooFewJointsSendNoCommandAndNameTheArm) {
  const Eigen::VectorXd sentinel = Sentinel(Side::kRight);
  q_[1] = q_[1].head(q_[1].size() - 1).eval();
  std::optional<std::string> emergency;
  EXPECT_FALSE(arms_.Retract(0.0, 0.01, &devices_->arms(), &emergency));
  ASSERT_TRUE(emergency.has_value());
  EXPECT_EQ(*emergency, "right arm: invalid joint readings");
  EXPECT_TRUE(target(Side::kRight).isApprox(sentinel));
}

// A followed pair out of reach for this instant (here: none to solve again)
// leaves the arm's last targets where they were on the object: they move with
// it, position exactly, the approach as near as the 4-DoF arm reaches.
TEST_F(GraspArmsTest, TargetsOutOfReachMoveOnWithTheObject) {
  const Platform& platform = devices_->platform();
  const ArmModel& arm = platform.arm(Side::kLeft);
  ArmGrasp g;
  g.side = Side::kLeft;
  g.q_grasp = platform.home(Side::kLeft) + Eigen::Vector4d(0.1, 0.3, -0.3, 0.0);
  g.q_precatch = platform.home(Side::kLeft) + Eigen::Vector4d(0.1, 0.15, -0.15, 0.0);
  arms_.Aim(0, g, 0.0);
  FollowView view;
  view.dMo.translation() = Eigen::Vector3d(0.075, 0.0, 0.46);
  const SwitchState none{-1, -1};
  ASSERT_FALSE(arms_.Step(0.0, 0.01, view, none, &devices_->arms()).has_value());
  const Eigen::Isometry3d bMg_before = arms_.grasp_target_bMg(0);
  EXPECT_TRUE(bMg_before.isApprox(arm.ForwardKinematics(g.q_grasp)));

  const Eigen::Isometry3d bMd = platform.dMb(Side::kLeft).inverse();
  const Eigen::Isometry3d bMo_before = bMd * view.dMo;
  view.dMo.translation() += Eigen::Vector3d(0.01, -0.015, 0.01);  // the vehicle sways
  ASSERT_FALSE(arms_.Step(0.01, 0.01, view, none, &devices_->arms()).has_value());
  const Eigen::Isometry3d moved = bMd * view.dMo * bMo_before.inverse() * bMg_before;
  const Eigen::Isometry3d& bMg = arms_.grasp_target_bMg(0);
  EXPECT_LT((bMg.translation() - moved.translation()).norm(), 1e-5);
  const double approach_rad =
      std::acos(std::clamp(bMg.linear().col(2).dot(moved.linear().col(2)), -1.0, 1.0));
  EXPECT_LT(approach_rad, 0.15);
  EXPECT_GT((bMg.translation() - bMg_before.translation()).norm(), 0.015);
}

}  // namespace
}  // namespace aerograsp
