#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/config.h"
#include "grasp/quality.h"

namespace aerograsp {
namespace {

const Eigen::Vector3d kCom = Eigen::Vector3d::Zero();

/// Two contacts on the z axis at +-r, pushing towards each other, each push
/// tilted by `tilt` rad towards +x (so both cones lean the same way).
std::vector<Wrench> TiltedPair(double tilt, const FrictionConfig& friction, double r = 0.05) {
  std::vector<Wrench> w;
  AppendContactWrenches(Eigen::Vector3d(0, 0, r),
                        Eigen::Vector3d(std::sin(tilt), 0, -std::cos(tilt)), kCom, 0.05, friction,
                        &w);
  AppendContactWrenches(Eigen::Vector3d(0, 0, -r),
                        Eigen::Vector3d(std::sin(tilt), 0, std::cos(tilt)), kCom, 0.05, friction,
                        &w);
  return w;
}

TEST(QualityTest, SixFrictionlessSoftContactsOnACubeMatchTheHandValue) {
  // Contacts at the six face centres of a cube (half side 0.05 m), pushing to
  // its centre; no friction, torsional friction gamma. Each contact gives the
  // wrenches (n, 0) and (n, +-gamma/rho n): per axis k a square with vertices
  // (+-1, +-g) in the (f_k, tau_k) plane, g = gamma / rho. The hull is the free
  // sum of three squares; its polar is the product of their polars
  // {|a| + g|b| <= 1}, so epsilon = min(1, g) / sqrt(3).
  FrictionConfig friction;
  friction.mu = 0.0;
  friction.torsional_m = 0.005;
  const double rho = 0.05;
  std::vector<Wrench> w;
  for (int k = 0; k < 3; ++k) {
    for (double s : {1.0, -1.0}) {
      const Eigen::Vector3d n = s * Eigen::Vector3d::Unit(k);
      AppendContactWrenches(0.05 * n, -n, kCom, rho, friction, &w);
    }
  }
  const WrenchQuality q = ComputeWrenchQuality(w);
  EXPECT_TRUE(q.force_closure);
  EXPECT_NEAR(q.epsilon, 0.1 / std::sqrt(3.0), 1e-9);

  // The support-function estimate is an upper bound of the exact value.
  const std::vector<Wrench> dirs = SupportDirections(512);
  const std::vector<float> h = SupportTable(w, dirs);
  const double bound = EpsilonUpperBound(h.data(), h.data(), static_cast<int>(h.size()));
  EXPECT_GE(bound, q.epsilon - 1e-6);
  EXPECT_LT(bound, 2.0 * q.epsilon);
}

TEST(QualityTest, ForceClosureFlipsExactlyAtTheFrictionAngle) {
  // Nguyen: two soft contacts are in force closure iff the line through them
  // lies inside both friction cones: tilt < atan(mu). With an even number of
  // cone edges, two edges lie in the tilt plane, so the polyhedral cone has the
  // exact friction angle there.
  FrictionConfig friction;
  friction.mu = 0.5;
  friction.cone_edges = 4;
  const double threshold = std::atan(friction.mu);
  EXPECT_TRUE(ComputeWrenchQuality(TiltedPair(0.0, friction)).force_closure);
  EXPECT_TRUE(ComputeWrenchQuality(TiltedPair(threshold - 0.01, friction)).force_closure);
  EXPECT_FALSE(ComputeWrenchQuality(TiltedPair(threshold + 0.01, friction)).force_closure);
  friction.mu = 0.3;
  EXPECT_FALSE(ComputeWrenchQuality(TiltedPair(std::atan(0.5) - 0.01, friction)).force_closure);
}

TEST(QualityTest, EpsilonShrinksAsTheContactsTilt) {
  FrictionConfig friction;
  const double e0 = ComputeWrenchQuality(TiltedPair(0.0, friction)).epsilon;
  const double e1 = ComputeWrenchQuality(TiltedPair(0.2, friction)).epsilon;
  const double e2 = ComputeWrenchQuality(TiltedPair(0.4, friction)).epsilon;
  EXPECT_GT(e0, e1);
  EXPECT_GT(e1, e2);
  EXPECT_GT(e2, 0.0);
}

TEST(QualityTest, PointContactPairCannotResistTorqueAboutItsAxis) {
  // Without torsional friction nothing resists a torque about the line through
  // two contacts: the wrenches span only 5 dimensions.
  FrictionConfig friction;
  friction.torsional_m = 0.0;
  const WrenchQuality q = ComputeWrenchQuality(TiltedPair(0.0, friction));
  EXPECT_FALSE(q.force_closure);
  EXPECT_EQ(q.epsilon, 0.0);
}

TEST(QualityTest, SameSidePairHasNoForceClosure) {
  // Both fingers on the top face pushing down: every force has f_z < 0.
  FrictionConfig friction;
  std::vector<Wrench> w;
  AppendContactWrenches(Eigen::Vector3d(0.03, 0, 0.05), -Eigen::Vector3d::UnitZ(), kCom, 0.05,
                        friction, &w);
  AppendContactWrenches(Eigen::Vector3d(-0.03, 0, 0.05), -Eigen::Vector3d::UnitZ(), kCom, 0.05,
                        friction, &w);
  const WrenchQuality q = ComputeWrenchQuality(w);
  EXPECT_FALSE(q.force_closure);
  EXPECT_EQ(q.epsilon, 0.0);
  const std::vector<Wrench> dirs = SupportDirections(64);
  const std::vector<float> h = SupportTable(w, dirs);
  // Direction +f_z is one of the first 12 axis directions: h <= 0 there.
  EXPECT_LE(EpsilonUpperBound(h.data(), h.data(), 64), 0.0);
}

TEST(QualityTest, DualGraspIsBetterThanEitherHalf) {
  // Two antipodal pairs on a sphere's x and y axes: the union's hull contains
  // each pair's hull, so its epsilon is at least as large.
  FrictionConfig friction;
  std::vector<Wrench> a, b;
  for (double s : {1.0, -1.0}) {
    AppendContactWrenches(s * 0.05 * Eigen::Vector3d::UnitX(), -s * Eigen::Vector3d::UnitX(), kCom,
                          0.05, friction, &a);
    AppendContactWrenches(s * 0.05 * Eigen::Vector3d::UnitY(), -s * Eigen::Vector3d::UnitY(), kCom,
                          0.05, friction, &b);
  }
  std::vector<Wrench> both = a;
  both.insert(both.end(), b.begin(), b.end());
  const double ea = ComputeWrenchQuality(a).epsilon, ed = ComputeWrenchQuality(both).epsilon;
  EXPECT_GT(ea, 0.0);
  EXPECT_GT(ed, ea);
  const std::vector<Wrench> dirs = SupportDirections(256);
  const std::vector<float> ha = SupportTable(a, dirs), hb = SupportTable(b, dirs);
  EXPECT_GE(EpsilonUpperBound(ha.data(), hb.data(), 256), ed - 1e-6);
}

TEST(QualityTest, SupportDirectionsAreUnitAndDeterministic) {
  const std::vector<Wrench> a = SupportDirections(100), b = SupportDirections(100);
  ASSERT_EQ(a.size(), 100u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].norm(), 1.0, 1e-12);
    EXPECT_EQ(a[i], b[i]);
  }
}

TEST(QualityTest, WeightShareIsEvenWithTheCentreOfMassBetweenTheGrasps) {
  const Eigen::Vector3d down(0, 0, 1);  // gravity in o
  const Eigen::Vector3d left(-0.1, 0, 0.02), right(0.1, 0, -0.03);
  WeightShare s = ComputeWeightShare(left, right, kCom, down, 0.1);
  EXPECT_NEAR(s.term, 1.0, 1e-12);
  EXPECT_NEAR(s.left_share, 0.5, 1e-12);
  // Centre of mass at 3/4 of the way: the right arm takes 3/4.
  s = ComputeWeightShare(left, right, Eigen::Vector3d(0.05, 0, 0), down, 0.1);
  EXPECT_NEAR(s.left_share, 0.25, 1e-12);
  EXPECT_NEAR(s.term, 0.5, 1e-12);
  // Off the line by 0.1 m: halved.
  s = ComputeWeightShare(left, right, Eigen::Vector3d(0, 0.1, 0), down, 0.1);
  EXPECT_NEAR(s.term, 0.5, 1e-12);
  // Outside the grasps: one arm would push down.
  s = ComputeWeightShare(left, right, Eigen::Vector3d(0.2, 0, 0), down, 0.1);
  EXPECT_EQ(s.term, 0.0);
  // Both grasps above each other on the gravity line: no share.
  EXPECT_EQ(
      ComputeWeightShare(Eigen::Vector3d(0, 0, 0.05), Eigen::Vector3d(0, 0, -0.05), kCom, down, 0.1)
          .term,
      0.0);
}

TEST(QualityTest, FrictionConfigValidationNamesTheKey) {
  FrictionConfig f;
  EXPECT_NO_THROW(f.Validate("plan.yaml", "friction."));
  f.cone_edges = 2;
  try {
    f.Validate("plan.yaml", "friction.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("plan.yaml: friction.cone_edges"));
  }
}

}  // namespace
}  // namespace aerograsp
