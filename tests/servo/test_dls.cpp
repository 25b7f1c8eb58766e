#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "servo/dls.h"

namespace aerograsp {
namespace {

TEST(DlsTest, UndampedAwayFromSingularitiesEqualsThePseudoInverse) {
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  Eigen::MatrixXd J(3, 4);
  for (int i = 0; i < J.size(); ++i) J(i) = g(rng);
  const Eigen::Vector3d e(0.1, -0.2, 0.3);
  const DlsSolution s = SolveDampedLeastSquares(J, e, DampingOptions{});
  EXPECT_EQ(s.damping, 0.0);
  EXPECT_TRUE(s.dq.isApprox(J.completeOrthogonalDecomposition().pseudoInverse() * e, 1e-10));
  EXPECT_TRUE((J * s.dq).isApprox(e, 1e-10));
}

TEST(DlsTest, NearASingularityMatchesTheClosedForm) {
  Eigen::MatrixXd J(3, 3);
  J << 1, 0, 0, 0, 1, 0, 0, 0, 1e-4;  // nearly singular
  const Eigen::Vector3d e(0.1, 0.1, 0.1);
  const DampingOptions options{0.04, 0.04};
  const DlsSolution s = SolveDampedLeastSquares(J, e, options);
  EXPECT_GT(s.damping, 0.0);
  EXPECT_NEAR(s.min_singular, 1e-4, 1e-12);
  const Eigen::MatrixXd closed =
      J.transpose() *
      (J * J.transpose() + s.damping * s.damping * Eigen::MatrixXd::Identity(3, 3)).inverse();
  EXPECT_TRUE(s.dq.isApprox(closed * e, 1e-9));
  // Bounded: the damped gain along the weak direction is at most 1 / (2 lambda).
  EXPECT_LT(std::abs(s.dq[2]), 0.1 / (2 * s.damping) + 1e-12);
}

TEST(DlsTest, DampingGrowsOnlyBelowTheThreshold) {
  const DampingOptions options{0.04, 0.05};
  auto damping_at = [&](double s_min) {
    Eigen::MatrixXd J = Eigen::MatrixXd::Identity(2, 2);
    J(1, 1) = s_min;
    return SolveDampedLeastSquares(J, Eigen::Vector2d(1, 1), options).damping;
  };
  EXPECT_EQ(damping_at(0.05), 0.0);
  EXPECT_GT(damping_at(0.02), 0.0);
  EXPECT_GT(damping_at(0.0), damping_at(0.02));
  EXPECT_NEAR(damping_at(0.0), 0.05, 1e-12);
}

TEST(DlsTest, SecondaryTaskLeavesTheFeasiblePrimaryUntouched) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  Eigen::MatrixXd J1(3, 4), J2(3, 4);
  for (int i = 0; i < J1.size(); ++i) J1(i) = g(rng);
  for (int i = 0; i < J2.size(); ++i) J2(i) = g(rng);
  const Eigen::Vector3d e1(0.1, 0.2, -0.1), e2(1.0, -1.0, 0.5);
  const DlsSolution s = SolvePrioritized(J1, e1, J2, e2, DampingOptions{});
  EXPECT_TRUE((J1 * s.dq).isApprox(e1, 1e-9));
  // The secondary gets closer than the primary alone would leave it.
  const Eigen::VectorXd dq1 = SolveDampedLeastSquares(J1, e1, DampingOptions{}).dq;
  EXPECT_LT((J2 * s.dq - e2).norm(), (J2 * dq1 - e2).norm());
}

}  // namespace
}  // namespace aerograsp
