#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "core/arm_ik.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

std::string Robot(const std::string& name) {
  return std::string(AEROGRASP_DATA_DIR) + "/robots/" + name;
}

ArmModel Arm(const std::string& file) {
  return ArmModel::FromUrdfFile(Robot(file), "base_link", "tool");
}

Eigen::VectorXd RandomWithinLimits(const ArmModel& arm, std::mt19937* rng) {
  Eigen::VectorXd q(arm.dof());
  for (int i = 0; i < arm.dof(); ++i) {
    q[i] =
        std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(*rng);
  }
  return q;
}

TEST(ArmIkTest, BothShippedArmsHaveClosedForms) {
  EXPECT_TRUE(ArmIk(Arm("arm4.urdf")).is_analytic());
  EXPECT_TRUE(ArmIk(Arm("arm6.urdf")).is_analytic());
}

// A chain whose wrist axes do not meet in one point has no closed form: the
// 6-DoF arm with its last joint moved off the wrist centre.
TEST(ArmIkTest, AWristWhoseAxesMissEachOtherIsSolvedNumerically) {
  std::ifstream in(Robot("arm6.urdf"));
  std::string urdf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = R"(<origin xyz="0.04 0 0" rpy="0 1.5707963267949 0"/>)";
  const std::size_t at = urdf.find(from);
  ASSERT_NE(at, std::string::npos);
  urdf.replace(at, from.size(), R"(<origin xyz="0.04 0.01 0" rpy="0 1.5707963267949 0"/>)");
  const ArmModel arm =
      ArmModel::FromUrdfString(urdf, "arm6 with an offset wrist", "base_link", "tool");
  EXPECT_FALSE(ArmIk(arm).is_analytic());
}

// The closed form of the 6-DoF arm finds the configuration a pose came from
// (nearest the seed, which is that configuration) and every solution it
// returns reaches the pose within the limits.
TEST(ArmIkTest, SixDofPoseSolutionsReproduceForwardKinematics) {
  const ArmModel arm = Arm("arm6.urdf");
  const ArmIk ik(arm);
  std::mt19937 rng(5);
  std::vector<Eigen::VectorXd> sols;
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    ASSERT_GT(ik.SolvePose(bMe, q, &sols), 0) << q.transpose();
    EXPECT_LT((sols[0] - q).norm(), 1e-6) << q.transpose() << " vs " << sols[0].transpose();
    for (const Eigen::VectorXd& s : sols) {
      EXPECT_TRUE(arm.WithinLimits(s));
      const PoseError err = ComparePoses(arm.ForwardKinematics(s), bMe);
      EXPECT_LT(err.translation_m, 1e-5);
      EXPECT_LT(err.rotation_rad, 1e-4);
    }
  }
}

TEST(ArmIkTest, PositionSolutionsReproduceForwardKinematics) {
  const ArmModel arm = Arm("arm4.urdf");
  const ArmIk ik(arm);
  std::mt19937 rng(7);
  std::vector<Eigen::VectorXd> sols;
  for (int trial = 0; trial < 500; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    ASSERT_GT(ik.SolvePosition(bMe.translation(), bMe.linear().col(0), q, &sols), 0)
        << q.transpose();
    // Sorted by distance to the seed: the first is the configuration FK came from.
    EXPECT_LT((sols[0] - q).norm(), 1e-6) << q.transpose() << " vs " << sols[0].transpose();
    for (const Eigen::VectorXd& s : sols) {
      EXPECT_TRUE(arm.WithinLimits(s));
      const Eigen::Isometry3d bMs = arm.ForwardKinematics(s);
      EXPECT_LT((bMs.translation() - bMe.translation()).norm(), 1e-6);
      // The closing axis is +-x: |x_s . x_e| = 1 whenever the approach is the same.
      if (bMs.linear().col(2).dot(bMe.linear().col(2)) > 1.0 - 1e-9) {
        EXPECT_NEAR(std::abs(bMs.linear().col(0).dot(bMe.linear().col(0))), 1.0, 1e-6);
      }
    }
  }
}

// The 6-DoF arm's position IK (the planner's pre-catch pose: the tool point
// moved back along the approach) keeps the seed's approach and closing axes.
TEST(ArmIkTest, SixDofPositionKeepsTheSeedsApproach) {
  const ArmModel arm = Arm("arm6.urdf");
  const ArmIk ik(arm);
  std::mt19937 rng(9);
  std::vector<Eigen::VectorXd> sols;
  int solved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    const Eigen::Vector3d p = bMe.translation() - 0.03 * bMe.linear().col(2);
    if (ik.SolvePosition(p, bMe.linear().col(0), q, &sols) == 0) continue;
    ++solved;
    const Eigen::Isometry3d bMs = arm.ForwardKinematics(sols[0]);
    EXPECT_LT((bMs.translation() - p).norm(), 1e-5);
    EXPECT_GT(bMs.linear().col(2).dot(bMe.linear().col(2)), 1.0 - 1e-8);
    EXPECT_GT(bMs.linear().col(0).dot(bMe.linear().col(0)), 1.0 - 1e-8);
  }
  EXPECT_GE(solved, 120);  // 3 cm back leaves the joint limits for some
}

// The nearest-only queries give exactly the first solution of the full ones
// (the planner and the servo take only that one), and none when those have none.
TEST(ArmIkTest, NearestQueriesGiveTheFullQueriesFirstSolution) {
  for (const char* urdf : {"arm4.urdf", "arm6.urdf"}) {
    const ArmModel arm = Arm(urdf);
    const ArmIk ik(arm);
    std::mt19937 rng(13);
    std::vector<Eigen::VectorXd> sols;
    Eigen::VectorXd nearest;
    int found = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
      const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
      // Seeds away from q: the nearest solution is not always q's branch.
      Eigen::VectorXd seed = q;
      for (int i = 0; i < arm.dof(); ++i)
        seed[i] += std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
      seed = arm.Clamp(seed);
      // Moved back along the approach: some of these leave the workspace.
      const Eigen::Vector3d p = bMe.translation() - 0.05 * bMe.linear().col(2);
      const int n = ik.SolvePosition(p, bMe.linear().col(0), seed, &sols);
      ASSERT_EQ(ik.SolvePositionNearest(p, bMe.linear().col(0), seed, &nearest), n > 0) << urdf;
      if (n > 0) {
        ++found;
        EXPECT_EQ(nearest, sols.front()) << urdf;
      }
      if (!ik.closed_form_solves_pose()) continue;
      const int m = ik.SolvePose(bMe, seed, &sols);
      ASSERT_EQ(ik.SolvePoseNearest(bMe, seed, &nearest), m > 0) << urdf;
      if (m > 0) EXPECT_EQ(nearest, sols.front()) << urdf;
    }
    EXPECT_GT(found, 30) << urdf;
    EXPECT_LT(found, 300) << urdf;
  }
}

TEST(ArmIkTest, OutOfReachHasNoSolution) {
  const ArmModel arm = Arm("arm4.urdf");
  const ArmIk ik(arm);
  std::vector<Eigen::VectorXd> sols;
  EXPECT_EQ(ik.SolvePosition(Eigen::Vector3d(0.0, 0.0, 0.6), Eigen::Vector3d::UnitX(),
                             Eigen::VectorXd::Zero(4), &sols),
            0);
  std::vector<GraspAxisSolution> grasps;
  EXPECT_EQ(ik.SolveGraspAxis(Eigen::Vector3d(0.5, 0.3, 0.4), Eigen::Vector3d::UnitY(), 0.0, 0.08,
                              Eigen::VectorXd::Zero(4), &grasps),
            0);
}

// Grasp-axis IK recovers a configuration whose fingers close along the given
// axis through the contact centre, with the contacts at a depth in range.
void CheckGraspAxis(const std::string& urdf, int trials, double min_success) {
  const ArmModel arm = Arm(urdf);
  const ArmIk ik(arm);
  std::mt19937 rng(11);
  std::vector<GraspAxisSolution> sols;
  int solved = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    const double depth = std::uniform_real_distribution<double>(0.0, 0.08)(rng);
    const Eigen::Vector3d c = bMe.translation() - depth * bMe.linear().col(2);
    const Eigen::Vector3d x = bMe.linear().col(0);
    // Seed near the truth, as the planner seeds from the current arm state.
    Eigen::VectorXd seed = q;
    seed.array() += 0.05;
    if (ik.SolveGraspAxis(c, x, 0.0, 0.08, arm.Clamp(seed), &sols) == 0) continue;
    ++solved;
    for (const GraspAxisSolution& s : sols) {
      EXPECT_TRUE(arm.WithinLimits(s.q));
      const Eigen::Isometry3d bMs = arm.ForwardKinematics(s.q);
      EXPECT_LT((bMs.matrix() - s.bMe.matrix()).norm(), 1e-12);
      EXPECT_NEAR(std::abs(bMs.linear().col(0).dot(x)), 1.0, 1e-6);
      EXPECT_GE(s.depth_m, 0.0 - 1e-12);
      EXPECT_LE(s.depth_m, 0.08 + 1e-12);
      // Position tolerance 1e-5 m plus the approach's 1e-4 rad over the depth.
      EXPECT_LT((bMs.translation() - (c + s.depth_m * bMs.linear().col(2))).norm(), 2e-5);
    }
  }
  EXPECT_GE(solved, min_success * trials) << urdf;
}

TEST(ArmIkTest, GraspAxisClosedFormFindsReachableGrasps) {
  // Every sample comes from a reachable pose, so the closed form must find it.
  CheckGraspAxis("arm4.urdf", 400, 1.0);
}

TEST(ArmIkTest, GraspAxisForSixDofArm) {
  // The closed form at 8 approach angles and the middle depth: most sampled
  // grasps are reachable with one of them.
  CheckGraspAxis("arm6.urdf", 400, 0.8);
}

TEST(ArmIkTest, GraspAxisDepthSamplesSpanThePadsAndReachMore) {
  // The 6-DoF arm's grasp-axis IK at 16 approaches and 3 depths: the depths
  // are the range's ends and middle, and the grasps of random contact centres
  // and closing axes it reaches include those 8 approaches at the middle reach.
  const ArmModel arm = Arm("arm6.urdf");
  const ArmIk coarse(arm);
  IkOptions options;
  options.approach_samples = 16;
  options.depth_samples = 3;
  const ArmIk fine(arm, options);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<GraspAxisSolution> sols;
  int coarse_solved = 0, fine_solved = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    // A contact centre near a reachable tool point, a closing axis anywhere.
    const Eigen::Vector3d c = bMe.translation() + 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d x = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const bool by_coarse = coarse.SolveGraspAxis(c, x, 0.025, 0.10, q, &sols) > 0;
    coarse_solved += by_coarse;
    const int n = fine.SolveGraspAxis(c, x, 0.025, 0.10, q, &sols);
    fine_solved += n > 0;
    if (by_coarse) EXPECT_GT(n, 0) << "trial " << trial;
    for (const GraspAxisSolution& s : sols) {
      const double d = s.depth_m;
      EXPECT_TRUE(std::abs(d - 0.025) < 1e-12 || std::abs(d - 0.0625) < 1e-12 ||
                  std::abs(d - 0.10) < 1e-12)
          << d;
      EXPECT_LT((s.bMe.translation() - (c + d * s.bMe.linear().col(2))).norm(), 2e-5);
    }
  }
  EXPECT_GT(fine_solved, coarse_solved + 10);
}

// The 6-DoF grasp-axis IK leaves out the approaches whose wrist centre no
// placement of the forearm reaches; what it gives is still, approach by
// approach, SolvePoseNearest's answer at every sampled tool pose, for contact
// centres from well inside the arm's reach to beyond it.
TEST(ArmIkTest, SixDofGraspAxisGivesEverySampledPosesNearestSolution) {
  const ArmModel arm = Arm("arm6.urdf");
  IkOptions options;
  options.approach_samples = 16;
  options.depth_samples = 3;
  const ArmIk ik(arm, options);
  const double depth_min = 0.025, depth_max = 0.10;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<GraspAxisSolution> sols;
  int solved = 0, unsolved = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::VectorXd q_seed = RandomWithinLimits(arm, &rng);
    // Around a reachable tool point, out to farther than the arm reaches.
    const Eigen::Vector3d c = arm.ForwardKinematics(RandomWithinLimits(arm, &rng)).translation() +
                              0.15 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d x = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const int n = ik.SolveGraspAxis(c, x, depth_min, depth_max, q_seed, &sols);
    // The sampled poses: approach angles about x from the same reference
    // perpendicular, the depths' ends and middle, both closing signs.
    Eigen::Index i;
    x.cwiseAbs().minCoeff(&i);
    const Eigen::Vector3d e1 = x.cross(Eigen::Vector3d::Unit(i)).normalized(), e2 = x.cross(e1);
    std::vector<Eigen::VectorXd> expected;
    for (int k = 0; k < 16 * 3; ++k) {
      const double depth = depth_min + (depth_max - depth_min) * (k / 16) / 2.0;
      const double phi = 2.0 * M_PI * (k % 16) / 16;
      const Eigen::Vector3d a = std::cos(phi) * e1 + std::sin(phi) * e2;
      bool found = false;
      Eigen::VectorXd best, q;
      for (double sign : {1.0, -1.0}) {
        Eigen::Isometry3d bMe = Eigen::Isometry3d::Identity();
        bMe.linear().col(0) = sign * x;
        bMe.linear().col(1) = a.cross(sign * x);
        bMe.linear().col(2) = a;
        bMe.translation() = c + depth * a;
        if (!ik.SolvePoseNearest(bMe, q_seed, &q)) continue;
        if (!found || (q - q_seed).squaredNorm() < (best - q_seed).squaredNorm()) best = q;
        found = true;
      }
      if (found) expected.push_back(best);
    }
    ASSERT_EQ(n, static_cast<int>(expected.size())) << "trial " << trial;
    std::stable_sort(expected.begin(), expected.end(),
                     [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
                       return (a - q_seed).squaredNorm() < (b - q_seed).squaredNorm();
                     });
    for (int k = 0; k < n; ++k) {
      EXPECT_LT((sols[k].q - expected[k]).norm(), 1e-9) << "trial " << trial;
    }
    (n > 0 ? solved : unsolved) += 1;
  }
  // Both kinds of contact centre were tried.
  EXPECT_GT(solved, 30);
  EXPECT_GT(unsolved, 30);
}

// The wrist's margin: the least distance of j3..j5 to their limits and of j4
// to the singularity at 0 (and +-pi); none on the 4-DoF arm.
TEST(ArmIkTest, WristMarginIsTheSixDofWristsDistanceToItsLimitsAndSingularity) {
  const ArmIk ik6(Arm("arm6.urdf"));
  Eigen::VectorXd q(6);
  // Shoulder and elbow at their limits count for nothing; j4 is 0.9 rad from
  // 0 and 0.845 rad from its limit.
  q << 1.5707963, -1.7453293, 2.6179939, 0.2, 0.9, -0.4;
  EXPECT_NEAR(ik6.WristMargin(q), 0.8453293, 1e-6);
  q[4] = -0.1;
  EXPECT_NEAR(ik6.WristMargin(q), 0.1, 1e-12);  // near the singularity
  q[4] = 0.6;
  q[3] = -1.8198622;
  EXPECT_NEAR(ik6.WristMargin(q), 0.1, 1e-6);  // j3 0.1 inside its lower limit
  const ArmIk ik4(Arm("arm4.urdf"));
  EXPECT_TRUE(std::isinf(ik4.WristMargin(Eigen::VectorXd::Zero(4))));
}

TEST(ArmIkTest, NumericPoseReachesForwardKinematicsTarget) {
  const ArmModel arm = Arm("arm6.urdf");
  const ArmIk ik(arm);
  std::mt19937 rng(3);
  int solved = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::VectorXd q = RandomWithinLimits(arm, &rng);
    Eigen::VectorXd seed = q;
    seed.array() += 0.1;
    Eigen::VectorXd sol;
    if (!ik.SolvePoseNumeric(arm.ForwardKinematics(q), arm.Clamp(seed), &sol)) continue;
    ++solved;
    const PoseError err = ComparePoses(arm.ForwardKinematics(sol), arm.ForwardKinematics(q));
    EXPECT_LT(err.translation_m, 1e-5);
    EXPECT_LT(err.rotation_rad, 1e-4);
  }
  EXPECT_GE(solved, 90);
}

}  // namespace
}  // namespace aerograsp
