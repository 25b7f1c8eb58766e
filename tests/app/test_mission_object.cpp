// The object as the mission knows it: while one gripper carries it, the
// frames that see it along its length say where it sits in that gripper; the
// motion fitted along its length before the attempt no longer applies.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "app/runtime/mission_config.h"
#include "app/runtime/mission_object.h"
#include "core/data_dir.h"
#include "core/symmetry.h"

namespace aerograsp {
namespace {

constexpr double kFramePeriodS = 1.0 / 30.0;

class TrackedObjectTest : public ::testing::Test {
 protected:
  TrackedObjectTest()
      : config_(MissionConfig::Load(DataPath("config/mission_default.yaml"))),
        object_(
            config_, Symmetry(),
            Eigen::AlignedBox3d(Eigen::Vector3d(-0.11, -0.045, -0.04),
                                Eigen::Vector3d(0.11, 0.045, 0.04)),
            kFramePeriodS, [this](int a) { return dMe_[a]; },
            [this](const std::string& line) { log_.push_back(line); }) {}
  static ObjectSymmetry Symmetry() {
    ObjectSymmetry s;
    s.rotations = {Eigen::Matrix3d::Identity()};
    return s;
  }
  /// A frame seeing the object at `along_m` on its length (x) from the
  /// approach waypoint; the world, the body and the camera coincide.
  void See(double t_s, double along_m, bool weak_direction_fixed) {
    ObjectEstimate e;
    e.stamp_s = t_s;
    e.valid = true;
    e.state = TrackState::kFound;
    e.confidence = 1.0;
    e.weak_direction_fixed = weak_direction_fixed;
    e.fMo = Eigen::Translation3d(config_.approach_w_m + Eigen::Vector3d(along_m, 0.0, 0.0)) *
            Eigen::Isometry3d::Identity();
    e.cMo = e.fMo;
    object_.Update(t_s, e, Eigen::Isometry3d::Identity());
  }
  double AlongNow(double t_s) {
    return object_.dMo(t_s, Eigen::Isometry3d::Identity()).translation().x() -
           config_.approach_w_m.x();
  }

  MissionConfig config_;
  std::vector<std::string> log_;
  // The tools in the body frame: at its origin unless a test moves them.
  Eigen::Isometry3d dMe_[2] = {Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity()};
  TrackedObject object_;
};

TEST_F(TrackedObjectTest, LockedLengthPlacesFramesThatMissTheEnds) {
  double t = 0.0;
  for (; t < 3.0; t += kFramePeriodS) See(t, 0.03 * t, true);  // crawling at 3 cm/s
  ASSERT_TRUE(object_.LockLength());
  See(t, 0.2, false);  // slid along its length: the fit places it
  EXPECT_NEAR(AlongNow(t), 0.03 * t, 2e-3);
}

TEST_F(TrackedObjectTest, CarriedObjectFollowsFramesThatSeeItsEnds) {
  double t = 0.0;
  for (; t < 3.0; t += kFramePeriodS) See(t, 0.03 * t, true);
  ASSERT_TRUE(object_.LockLength());
  // A gripper takes it where the fit puts it; it stops there (it moves with
  // the gripper, which keeps still), 5 cm short of the fit's place 1 s on.
  object_.CarriedBy(0, object_.dMo(t, Eigen::Isometry3d::Identity()));
  const double held_m = 0.03 * t - 0.05;
  for (const double end_s = t + 2.0; t < end_s; t += kFramePeriodS) See(t, held_m, true);
  EXPECT_NEAR(AlongNow(t), held_m, 2e-3);
}

TEST_F(TrackedObjectTest, AnEmptyCloseNearAnEndMovesTheCarriedObjectThatEndToTheTool) {
  See(0.0, 0.0, true);
  const Eigen::Isometry3d dMo = object_.dMo(0.0, Eigen::Isometry3d::Identity());
  object_.CarriedBy(0, dMo);
  // The right tool 12 mm inside the +x end (the crawler's ends at +-0.11 m),
  // closing across the length (its x axis along y of o): it closed on nothing.
  dMe_[1] = dMo * Eigen::Translation3d(0.098, 0.0, -0.05) *
            Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  ASSERT_TRUE(object_.ClosedOnNothing(1));
  const Eigen::Isometry3d oMe = object_.dMo(0.0, Eigen::Isometry3d::Identity()).inverse() * dMe_[1];
  EXPECT_NEAR(oMe.translation().x(), 0.11, 1e-9);   // the end at the tool
  EXPECT_NEAR(oMe.translation().z(), -0.05, 1e-9);  // only along the length
  EXPECT_NE(log_.back().find("right gripper closed on nothing 12 mm"), std::string::npos)
      << log_.back();
}

TEST_F(TrackedObjectTest, AnEmptyCloseFarFromTheEndsOrAlongTheLengthLeavesTheObject) {
  See(0.0, 0.0, true);
  const Eigen::Isometry3d dMo = object_.dMo(0.0, Eigen::Isometry3d::Identity());
  object_.CarriedBy(0, dMo);
  const Eigen::Isometry3d across =
      Eigen::Isometry3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  dMe_[1] = dMo * Eigen::Translation3d(0.0, 0.0, -0.05) * across;  // 110 mm from either end
  EXPECT_FALSE(object_.ClosedOnNothing(1));
  dMe_[1] = dMo * Eigen::Translation3d(0.098, 0.0, -0.05);  // closing along the length
  EXPECT_FALSE(object_.ClosedOnNothing(1));
  EXPECT_FALSE(object_.ClosedOnNothing(0));  // the holder itself
  EXPECT_TRUE(object_.dMo(0.0, Eigen::Isometry3d::Identity()).isApprox(dMo, 1e-12));
}

TEST_F(TrackedObjectTest, AnEmptyCloseWithNothingCarriedSaysNothing) {
  See(0.0, 0.0, true);
  dMe_[1] = object_.dMo(0.0, Eigen::Isometry3d::Identity()) *
            Eigen::Translation3d(0.098, 0.0, -0.05) *
            Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  EXPECT_FALSE(object_.ClosedOnNothing(1));
}

}  // namespace
}  // namespace aerograsp
