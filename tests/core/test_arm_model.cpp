#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/arm_model.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

std::string Robot(const std::string& name) {
  return std::string(AEROGRASP_DATA_DIR) + "/robots/" + name;
}

Eigen::VectorXd RandomWithinLimits(const ArmModel& arm, std::mt19937* rng) {
  Eigen::VectorXd q(arm.dof());
  for (int i = 0; i < arm.dof(); ++i) {
    q[i] =
        std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(*rng);
  }
  return q;
}

// Central differences of forward kinematics: linear part from the tip origin,
// angular part from the rotation increment, both in the base frame.
Eigen::Matrix<double, 6, Eigen::Dynamic> NumericJacobian(const ArmModel& arm,
                                                         const Eigen::VectorXd& q) {
  const double h = 1e-6;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, arm.dof());
  for (int i = 0; i < arm.dof(); ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += h;
    qm[i] -= h;
    const Eigen::Isometry3d bMp = arm.ForwardKinematics(qp), bMm = arm.ForwardKinematics(qm);
    J.block<3, 1>(0, i) = (bMp.translation() - bMm.translation()) / (2 * h);
    J.block<3, 1>(3, i) = ThetaU(bMp.linear() * bMm.linear().transpose()) / (2 * h);
  }
  return J;
}

class ArmJacobianTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ArmJacobianTest, MatchesFiniteDifferencesAtRandomConfigurations) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot(GetParam()), "base_link", "tool");
  std::mt19937 rng(42);
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    const Eigen::MatrixXd J = arm.Jacobian(q);
    const Eigen::MatrixXd J_fd = NumericJacobian(arm, q);
    ASSERT_LT((J - J_fd).cwiseAbs().maxCoeff(), 1e-7) << "q = " << q.transpose();
  }
}

TEST_P(ArmJacobianTest, KinematicsAgreesWithForwardKinematics) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot(GetParam()), "base_link", "tool");
  std::mt19937 rng(7);
  const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  arm.Kinematics(q, &bMe, &J);
  EXPECT_TRUE(bMe.isApprox(arm.ForwardKinematics(q), 1e-12));
  std::vector<Eigen::Isometry3d> bMs;
  arm.SegmentPoses(q, &bMs);
  ASSERT_EQ(bMs.size(), static_cast<std::size_t>(arm.dof() + 2));
  EXPECT_TRUE(bMs.back().isApprox(bMe, 1e-12));
}

INSTANTIATE_TEST_SUITE_P(ShippedArms, ArmJacobianTest, ::testing::Values("arm4.urdf", "arm6.urdf"));

TEST(ArmModelTest, FourDofChainMatchesFacts) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot("arm4.urdf"), "base_link", "tool");
  ASSERT_EQ(arm.dof(), 4);
  EXPECT_EQ(arm.joint_names(), (std::vector<std::string>{"j0", "j1", "j2", "j3"}));
  const double deg = M_PI / 180.0;
  EXPECT_NEAR(arm.lower_limits()[1], -100 * deg, 1e-6);
  EXPECT_NEAR(arm.upper_limits()[1], 30 * deg, 1e-6);
  EXPECT_NEAR(arm.lower_limits()[2], -15 * deg, 1e-6);
  EXPECT_NEAR(arm.upper_limits()[2], 150 * deg, 1e-6);
  EXPECT_NEAR(arm.upper_limits()[3], 110 * deg, 1e-6);
  // Stretched reach from the shoulder: 0.148 + 0.06 + 0.02 + 0.215 m.
  EXPECT_NEAR(arm.StretchedReach(), 0.443, 1e-9);
  // At q = 0 the arm is stretched along base z: tool at 0.02 + 0.03 + 0.03 + 0.443 m.
  const Eigen::Isometry3d bMe = arm.ForwardKinematics(Eigen::VectorXd::Zero(4));
  EXPECT_TRUE(bMe.translation().isApprox(Eigen::Vector3d(0, 0, 0.523), 1e-9));
  // The approach axis (tool z) runs along the arm.
  EXPECT_TRUE(bMe.linear().col(2).isApprox(Eigen::Vector3d::UnitZ(), 1e-9));
}

TEST(ArmModelTest, ShoulderPitchTiltsTheUpperArmForwardForNegativeAngles) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot("arm4.urdf"), "base_link", "tool");
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4);
  q[1] = -M_PI / 2;  // upper arm horizontal
  const Eigen::Vector3d p = arm.ForwardKinematics(q).translation();
  EXPECT_NEAR(p.x(), 0.443, 1e-9);
  EXPECT_NEAR(p.z(), 0.08, 1e-9);
}

TEST(ArmModelTest, SixDofHasWristAndShorterTool) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot("arm6.urdf"), "base_link", "tool");
  ASSERT_EQ(arm.dof(), 6);
  // 0.148 + 0.06 + 0.115 + 0.04 + 0.02 + 0.13 m
  EXPECT_NEAR(arm.StretchedReach(), 0.513, 1e-9);
  // The 6-DoF arm can turn its approach axis about the wrist pitch.
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  q[4] = M_PI / 2;
  const Eigen::Vector3d z = arm.ForwardKinematics(q).linear().col(2);
  EXPECT_NEAR(std::abs(z.z()), 0.0, 1e-9);
}

TEST(ArmModelTest, SegmentsCarryTheGripperAndFingers) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot("arm4.urdf"), "base_link", "tool");
  ASSERT_EQ(arm.segments().size(), 5u);
  const ArmSegment& last = arm.segments().back();
  EXPECT_THAT(last.link_names,
              ::testing::IsSupersetOf({"wrist", "gripper_base", "finger_a", "finger_b", "tool"}));
  EXPECT_EQ(last.collision.size(), 4u);  // wrist, housing, two fingers
  double mass = 0.0;
  for (const ArmSegment& s : arm.segments()) mass += s.mass_kg;
  EXPECT_NEAR(mass, 0.632, 0.01);  // 632 g per 4-DoF arm, docs/hardware.md
}

TEST(ArmModelTest, LimitsHelpers) {
  const ArmModel arm = ArmModel::FromUrdfFile(Robot("arm4.urdf"), "base_link", "tool");
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4);
  EXPECT_TRUE(arm.WithinLimits(q));
  q[2] = 3.0;
  EXPECT_FALSE(arm.WithinLimits(q));
  EXPECT_TRUE(arm.WithinLimits(arm.Clamp(q)));
  q[2] = NAN;
  EXPECT_FALSE(arm.WithinLimits(q));
  EXPECT_FALSE(arm.WithinLimits(Eigen::VectorXd::Zero(3)));
}

// A two-joint URDF with a placeholder to break in each test.
std::string TwoJointUrdf(
    const std::string& j2_type = "revolute",
    const std::string& j2_limit = R"(<limit lower="-1" upper="1" effort="1" velocity="2"/>)",
    const std::string& j2_axis = "0 0 1") {
  return R"(<robot name="t">
  <link name="a"/><link name="b"/><link name="c"/><link name="side"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="2"/></joint>
  <joint name="j2" type=")" +
         j2_type + R"("><parent link="b"/><child link="c"/>
    <origin xyz="0.2 0 0"/><axis xyz=")" +
         j2_axis + R"("/>)" + j2_limit + R"(</joint>
  <joint name="js" type="fixed"><parent link="a"/><child link="side"/></joint>
</robot>)";
}

TEST(ArmModelTest, ReadsAValidChain) {
  const ArmModel arm = ArmModel::FromUrdfString(TwoJointUrdf(), "t.urdf", "a", "c");
  EXPECT_EQ(arm.dof(), 2);
  EXPECT_TRUE(arm.ForwardKinematics(Eigen::Vector2d(0, 0))
                  .translation()
                  .isApprox(Eigen::Vector3d(0.2, 0, 0.1)));
}

TEST(ArmModelTest, RejectsMissingLinkAndListsTheLinks) {
  try {
    ArmModel::FromUrdfString(TwoJointUrdf(), "t.urdf", "a", "tool");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("t.urdf: no link named 'tool'"));
    EXPECT_THAT(e.what(), HasSubstr("links: a, b, c, side"));
  }
}

TEST(ArmModelTest, RejectsLinksThatAreNotASerialChain) {
  EXPECT_THROW(
      {
        try {
          ArmModel::FromUrdfString(TwoJointUrdf(), "t.urdf", "c", "side");
        } catch (const UrdfError& e) {
          EXPECT_THAT(e.what(), HasSubstr("link 'side' is not below link 'c'"));
          throw;
        }
      },
      UrdfError);
}

TEST(ArmModelTest, RejectsInvertedLimits) {
  try {
    ArmModel::FromUrdfString(
        TwoJointUrdf("revolute", R"(<limit lower="2.6" upper="1.5" effort="1" velocity="2"/>)"),
        "bad.urdf", "a", "c");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.urdf: joint 'j2' has lower limit 2.6 >= upper limit 1.5"));
  }
}

TEST(ArmModelTest, RejectsZeroVelocityLimit) {
  try {
    ArmModel::FromUrdfString(
        TwoJointUrdf("revolute", R"(<limit lower="-1" upper="1" effort="1" velocity="0"/>)"),
        "bad.urdf", "a", "c");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("joint 'j2' has velocity limit 0: must be positive"));
  }
}

TEST(ArmModelTest, RejectsFloatingJointOnTheChain) {
  try {
    ArmModel::FromUrdfString(TwoJointUrdf("floating", ""), "bad.urdf", "a", "c");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("joint 'j2' is floating or planar"));
  }
}

TEST(ArmModelTest, RejectsChainWithoutMovingJoints) {
  try {
    ArmModel::FromUrdfString(TwoJointUrdf(), "t.urdf", "a", "side");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no moving joint between 'a' and 'side'"));
  }
}

TEST(ArmModelTest, RejectsMalformedXmlWithTheParsersReason) {
  try {
    ArmModel::FromUrdfString("<robot name='x'><link name='a'>", "broken.urdf", "a", "b");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("broken.urdf: not a valid URDF"));
  }
}

TEST(ArmModelTest, RejectsMissingFile) {
  try {
    ArmModel::FromUrdfFile("/nonexistent/arm.urdf", "a", "b");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("/nonexistent/arm.urdf: cannot open file"));
  }
}

TEST(StaticFrameTreeTest, VehicleMountsMatchFacts) {
  const StaticFrameTree tree = StaticFrameTree::FromUrdfFile(Robot("vehicle.urdf"));
  EXPECT_EQ(tree.root(), "body");
  EXPECT_TRUE(tree.Get("arm_left_mount")
                  .rootMlink.translation()
                  .isApprox(Eigen::Vector3d(0, -0.1525, 0.04)));
  EXPECT_TRUE(tree.Get("arm_right_mount")
                  .rootMlink.translation()
                  .isApprox(Eigen::Vector3d(0, 0.1525, 0.04)));
  EXPECT_EQ(tree.Get("safe_volume").collision.size(), 1u);
  EXPECT_EQ(tree.Find("nope"), nullptr);
  EXPECT_THROW(tree.Get("nope"), UrdfError);
}

TEST(StaticFrameTreeTest, RejectsMovingJoints) {
  try {
    StaticFrameTree::FromUrdfString(TwoJointUrdf(), "moving.urdf");
    FAIL() << "expected UrdfError";
  } catch (const UrdfError& e) {
    EXPECT_THAT(e.what(), HasSubstr("moving.urdf: joint 'j1' is not fixed"));
  }
}

}  // namespace
}  // namespace aerograsp
