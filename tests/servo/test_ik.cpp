#include <gtest/gtest.h>

#include <random>

#include "servo/ik.h"

namespace aerograsp {
namespace {

ArmModel Arm(const char* urdf) {
  return ArmModel::FromUrdfFile(std::string(AEROGRASP_DATA_DIR) + "/robots/" + urdf, "base_link",
                                "tool");
}

Eigen::Isometry3d Pose(const Eigen::Vector3d& t, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = R;
  M.translation() = t;
  return M;
}

TEST(ApproachErrorTest, SplitsSwingAndRoll) {
  const Eigen::Isometry3d bMg = Pose({0.1, 0.2, 0.3}, Eigen::Matrix3d::Identity());
  // A pure roll about z: no approach error.
  const Eigen::Isometry3d rolled =
      Pose({0.1, 0.2, 0.3}, Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  ApproachError e = ComputeApproachError(rolled, bMg);
  EXPECT_NEAR(e.approach_rad, 0.0, 1e-12);
  EXPECT_NEAR(e.roll_rad, 0.4, 1e-12);  // turning e by +0.4 about z reaches g
  EXPECT_NEAR(e.position_b.norm(), 0.0, 1e-12);
  // A pure tilt about x: approach error, no roll; the swing takes z_e onto z_g.
  const Eigen::Isometry3d tilted =
      Pose({0.0, 0.2, 0.3}, Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix());
  e = ComputeApproachError(tilted, bMg);
  EXPECT_NEAR(e.approach_rad, 0.3, 1e-12);
  EXPECT_NEAR(e.roll_rad, 0.0, 1e-12);
  EXPECT_TRUE(e.position_b.isApprox(Eigen::Vector3d(0.1, 0, 0), 1e-12));
  const Eigen::Vector3d z_swung =
      Eigen::AngleAxisd(e.swing_b.norm(), e.swing_b.normalized()) * tilted.linear().col(2);
  EXPECT_TRUE(z_swung.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // Opposite approach axes: angle pi, still finite.
  const Eigen::Isometry3d flipped =
      Pose({0.1, 0.2, 0.3}, Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix());
  e = ComputeApproachError(flipped, bMg);
  EXPECT_NEAR(e.approach_rad, M_PI, 1e-9);
  EXPECT_TRUE(e.swing_b.allFinite());
}

// The IK's step uses the geometric Jacobian's angular rows as the derivative of
// the error vector swing + roll * z_e: near a solution their first-order change
// must agree (checked against finite differences of the error).
TEST(ApproachErrorTest, ErrorChangesAsTheJacobianPredicts) {
  const ArmModel arm = Arm("arm6.urdf");
  Eigen::VectorXd q(6), dq(6);
  q << 0.3, -0.7, 1.2, 0.4, -0.5, 0.2;
  dq << 0.3, -0.2, 0.1, 0.5, -0.4, 0.2;
  const Eigen::Isometry3d bMg = arm.ForwardKinematics(q);
  const double h = 1e-6;
  const Eigen::Matrix<double, 6, Eigen::Dynamic> J = arm.Jacobian(q);
  const ApproachError e = ComputeApproachError(arm.ForwardKinematics(q + h * dq), bMg);
  const Eigen::Vector3d rot_error = e.swing_b + e.roll_rad * bMg.linear().col(2);
  // Moving by h*dq, the error is minus the motion: -J h dq to first order.
  EXPECT_TRUE((e.position_b / h).isApprox(-(J.topRows<3>() * dq), 1e-4));
  EXPECT_TRUE((rot_error / h).isApprox(-(J.bottomRows<3>() * dq), 1e-4));
}

class ArmIkTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ArmIkTest, SolvesTheForwardKinematicsOfRandomJointsFromFarSeeds) {
  const ArmModel arm = Arm(GetParam());
  const ApproachIkOptions options;
  const ApproachIk ik(arm, options);
  std::mt19937 rng(3), seed_rng(7);
  int solved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::VectorXd q_goal = DrawJointsWithinLimits(arm, &rng);
    const Eigen::Isometry3d bMg = arm.ForwardKinematics(q_goal);
    // The zero pose, then random seeds, as the servo's search tries them
    // after the closed-form ones.
    ApproachIkResult r =
        ik.SolveFrom(bMg, Eigen::VectorXd::Zero(arm.dof()), options.iterations_per_seed);
    for (int k = 0; k < options.random_seeds && !r.converged; ++k) {
      r = ik.SolveFrom(bMg, DrawJointsWithinLimits(arm, &seed_rng), options.iterations_per_seed);
    }
    if (!r.converged) continue;
    ++solved;
    EXPECT_TRUE(arm.WithinLimits(r.q));
    const ApproachError e = ComputeApproachError(arm.ForwardKinematics(r.q), bMg);
    EXPECT_LE(e.position_b.norm(), 1e-4);
    EXPECT_LE(e.approach_rad, 1e-3);
  }
  EXPECT_GE(solved, 198) << GetParam();  // 25 seeds: a rare target needs more
}

INSTANTIATE_TEST_SUITE_P(Arms, ArmIkTest, ::testing::Values("arm4.urdf", "arm6.urdf"));

TEST(ArmIkTest, TheSixDofArmsClosedFormSeedsAreSolutions) {
  const ArmModel arm = Arm("arm6.urdf");
  const ApproachIkOptions options;
  const ApproachIk ik(arm, options);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Isometry3d bMg = arm.ForwardKinematics(DrawJointsWithinLimits(arm, &rng));
    const std::vector<Eigen::VectorXd> seeds = ik.ClosedFormSeeds(bMg, Eigen::VectorXd::Zero(6));
    ASSERT_FALSE(seeds.empty()) << "trial " << trial;
    for (const Eigen::VectorXd& seed : seeds) {
      const ApproachIkResult r = ik.SolveFrom(bMg, seed, options.iterations_per_seed);
      EXPECT_TRUE(r.converged) << "trial " << trial;
      EXPECT_EQ(r.iterations, 1) << "trial " << trial;  // converged where it started
    }
  }
}

TEST(ArmIkTest, OnlyTheSixDofArmsClosedFormGivesEverySolution) {
  EXPECT_TRUE(ApproachIk(Arm("arm6.urdf"), ApproachIkOptions{}).closed_form_complete());
  EXPECT_FALSE(ApproachIk(Arm("arm4.urdf"), ApproachIkOptions{}).closed_form_complete());
  // With the roll free, the closed form (one roll per branch) is not all there is.
  EXPECT_FALSE(ApproachIk(Arm("arm6.urdf"), ApproachIkOptions{}, Eigen::Vector3d(1.0, 1.0, 0.0))
                   .closed_form_complete());
}

TEST(ArmIkTest, AFourDofPoseWithAnUnreachableApproachAxisIsNotSolved) {
  const ArmModel arm = Arm("arm4.urdf");
  const ApproachIk ik(arm, ApproachIkOptions{});
  Eigen::VectorXd q(4);
  q << 0.2, -0.6, 1.4, 0.3;
  // Same position, approach axis tilted sideways by 0.5 rad: the 4-DoF arm's
  // approach axis is set by its position, so no joints meet both.
  Eigen::Isometry3d bMg = arm.ForwardKinematics(q);
  bMg.linear() = bMg.linear() * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const ApproachIkResult r = ik.SolveFrom(bMg, q, ApproachIkOptions{}.iterations_per_seed);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(arm.WithinLimits(r.q));
  // With the approach and roll weights at zero only the position counts.
  const ApproachIk position_only(arm, ApproachIkOptions{}, Eigen::Vector3d::Zero());
  EXPECT_TRUE(position_only.SolveFrom(bMg, q, ApproachIkOptions{}.iterations_per_seed).converged);
}

}  // namespace
}  // namespace aerograsp
