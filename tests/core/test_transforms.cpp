#include <gtest/gtest.h>
#include <visp3/core/vpHomogeneousMatrix.h>

#include <cmath>
#include <random>

#include "core/conversions.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

TEST(TransformsTest, RpyRoundTripsAwayFromGimbalLock) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), pitch(-1.5, 1.5);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d rpy(angle(rng), pitch(rng), angle(rng));
    const Eigen::Matrix3d R = RotationFromRpy(rpy);
    EXPECT_TRUE(RotationFromRpy(RpyFromRotation(R)).isApprox(R, 1e-9));
  }
}

TEST(TransformsTest, RpyAtGimbalLockStillReproducesTheRotation) {
  const Eigen::Matrix3d R = RotationFromRpy({0.3, -M_PI / 2, 1.2});
  EXPECT_TRUE(RotationFromRpy(RpyFromRotation(R)).isApprox(R, 1e-9));
}

TEST(TransformsTest, RpyFollowsUrdfFixedAxisOrder) {
  // Yaw 90 deg after roll 90 deg: x stays horizontal and turns to y.
  const Eigen::Matrix3d R = RotationFromRpy({M_PI / 2, 0, M_PI / 2});
  EXPECT_TRUE(R.col(0).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE(R.col(1).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(TransformsTest, QuaternionIsWxyzWithNonNegativeW) {
  const Eigen::Isometry3d aMb = MakeTransformWxyz({1, 2, 3}, {-0.5, -0.5, -0.5, -0.5});
  const Eigen::Vector4d q = QuaternionWxyz(aMb);
  EXPECT_NEAR(q[0], 0.5, 1e-12);
  EXPECT_TRUE(aMb.isApprox(MakeTransformWxyz({1, 2, 3}, q)));
}

TEST(TransformsTest, RotationAngleIsAccurateNearZeroAndPi) {
  for (double a : {1e-9, 1e-4, 0.5, M_PI - 1e-6, M_PI}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(a, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
    EXPECT_NEAR(RotationAngle(R), a, 1e-9) << a;
  }
}

TEST(TransformsTest, ComparePosesGivesDistanceAndAngle) {
  const Eigen::Isometry3d a = MakeTransform({0, 0, 0}, {0, 0, 0});
  const Eigen::Isometry3d b = MakeTransform({0.03, 0.04, 0}, {0, 0, 0.1});
  const PoseError e = ComparePoses(a, b);
  EXPECT_NEAR(e.translation_m, 0.05, 1e-12);
  EXPECT_NEAR(e.rotation_rad, 0.1, 1e-12);
}

TEST(TransformsTest, SkewIsTheCrossProduct) {
  const Eigen::Vector3d v(1, -2, 3), w(0.5, 4, -1);
  EXPECT_TRUE((Skew(v) * w).isApprox(v.cross(w)));
}

TEST(TransformsTest, IsValidTransformRejectsNanAndScaling) {
  Eigen::Isometry3d M = MakeTransform({1, 2, 3}, {0.1, 0.2, 0.3});
  EXPECT_TRUE(IsValidTransform(M));
  M.linear() *= 1.01;
  EXPECT_FALSE(IsValidTransform(M));
  M = Eigen::Isometry3d::Identity();
  M.translation().x() = NAN;
  EXPECT_FALSE(IsValidTransform(M));
}

TEST(ConversionsTest, VispRoundTripAndComposition) {
  const Eigen::Isometry3d aMb = MakeTransform({0.1, -0.2, 0.3}, {0.4, -0.5, 0.6});
  const Eigen::Isometry3d bMc = MakeTransform({-0.7, 0.8, 0.05}, {-1.0, 0.2, 2.5});
  const vpHomogeneousMatrix vp_aMb = ToVisp(aMb), vp_bMc = ToVisp(bMc);
  EXPECT_TRUE(FromVisp(vp_aMb).isApprox(aMb, 1e-12));
  // ViSP composes the same way: aMc = aMb * bMc.
  EXPECT_TRUE(FromVisp(vp_aMb * vp_bMc).isApprox(aMb * bMc, 1e-12));
  // And ViSP's own rotation vector agrees with ours.
  const vpThetaUVector tu(vp_aMb.getRotationMatrix());
  const Eigen::Vector3d ours = ThetaU(aMb.linear());
  EXPECT_NEAR(tu[0], ours.x(), 1e-9);
  EXPECT_NEAR(tu[1], ours.y(), 1e-9);
  EXPECT_NEAR(tu[2], ours.z(), 1e-9);
}

TEST(ConversionsTest, PclMatrixRoundTripKeepsARotation) {
  const Eigen::Isometry3d aMb = MakeTransform({0.1, -0.2, 0.3}, {0.4, -0.5, 0.6});
  const Eigen::Isometry3d back = FromPclMatrix(ToPclMatrix(aMb));
  EXPECT_TRUE(IsValidTransform(back, 1e-9));
  EXPECT_LT(ComparePoses(aMb, back).translation_m, 1e-6);
  EXPECT_LT(ComparePoses(aMb, back).rotation_rad, 1e-6);
}

}  // namespace
}  // namespace aerograsp
