#include <gtest/gtest.h>

#include "core/random.h"
#include "core/transforms.h"
#include "detection/pose_ekf.h"

namespace aerograsp {
namespace {

/// The truth: constant linear and angular velocity in c.
Eigen::Isometry3d MovingPose(double t) {
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  cMo.translation() = Eigen::Vector3d(0.05, -0.02, 0.8) + t * Eigen::Vector3d(0.06, 0.03, -0.04);
  cMo.linear() =
      Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix() *
      RotationFromRpy(Eigen::Vector3d(2.0, 0.1, 0.5));
  return cMo;
}

Eigen::Matrix<double, 6, 6> Noise(double sp, double sr) {
  Eigen::Matrix<double, 6, 6> R = Eigen::Matrix<double, 6, 6>::Zero();
  R.diagonal() << sp * sp, sp * sp, sp * sp, sr * sr, sr * sr, sr * sr;
  return R;
}

TEST(PoseEkfTest, LearnsConstantVelocityAndPredictsAhead) {
  PoseEkfOptions
      options;  // the truth has no acceleration: trust the model more than the default does
  options.accel_noise_mps2 = 0.02;
  options.angular_accel_noise_radps2 = 0.05;
  PoseEkf ekf(options);
  FastRandom rng(3);
  const double dt = 1.0 / 30.0;
  ekf.Initialize(MovingPose(0.0), 0.0);
  for (int k = 1; k <= 90; ++k) {
    ekf.Predict(k * dt);
    Eigen::Isometry3d z = MovingPose(k * dt);
    z.translation() += 0.001 * Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
    ASSERT_TRUE(ekf.Update(z, Noise(0.001, 0.01)).accepted) << "frame " << k;
  }
  EXPECT_NEAR(ekf.v_f().x(), 0.06, 0.01);
  EXPECT_NEAR(ekf.v_f().z(), -0.04, 0.01);
  EXPECT_NEAR(ekf.w_f().norm(), 0.3, 0.05);
  // Predict 5 frames ahead without measurements: the motion carries on.
  const double t_ahead = 95 * dt;
  ekf.Predict(t_ahead);
  const PoseError e = ComparePoses(MovingPose(t_ahead), ekf.fMo());
  EXPECT_LT(e.translation_m, 0.003);
  EXPECT_LT(e.rotation_rad, 0.01);
  // A constant-pose model would be off by the motion of those 5 frames (> 10 mm).
  EXPECT_GT(ComparePoses(MovingPose(t_ahead), MovingPose(90 * dt)).translation_m, 0.01);
}

TEST(PoseEkfTest, GatesAnOutlierAndLeavesTheStateAlone) {
  PoseEkf ekf;
  const double dt = 1.0 / 30.0;
  ekf.Initialize(MovingPose(0.0), 0.0);
  for (int k = 1; k <= 30; ++k) {
    ekf.Predict(k * dt);
    ekf.Update(MovingPose(k * dt), Noise(0.001, 0.01));
  }
  ekf.Predict(31 * dt);
  const Eigen::Isometry3d before = ekf.fMo();
  Eigen::Isometry3d outlier = MovingPose(31 * dt);
  outlier.translation().x() += 0.10;
  const EkfUpdate gated = ekf.Update(outlier, Noise(0.001, 0.01));
  EXPECT_FALSE(gated.accepted);
  EXPECT_GT(gated.nis, 22.46);
  EXPECT_TRUE(ekf.fMo().isApprox(before));
  // A rotation outlier is gated too.
  Eigen::Isometry3d turned = MovingPose(31 * dt);
  turned.linear() =
      Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix() * turned.linear();
  EXPECT_FALSE(ekf.Update(turned, Noise(0.001, 0.01)).accepted);
  // The right measurement passes with a small innovation.
  const EkfUpdate good = ekf.Update(MovingPose(31 * dt), Noise(0.001, 0.01));
  EXPECT_TRUE(good.accepted);
  EXPECT_LT(good.nis, 12.6);
}

TEST(PoseEkfTest, PredictIgnoresOldStampsAndCapsLongGaps) {
  PoseEkfOptions options;
  options.max_predict_dt_s = 0.5;
  PoseEkf ekf(options);
  EXPECT_FALSE(ekf.initialized());
  ekf.Predict(1.0);  // not initialised: no-op, no crash
  ekf.Initialize(MovingPose(0.0), 1.0);
  ekf.Predict(0.5);
  EXPECT_DOUBLE_EQ(ekf.stamp_s(), 1.0);
  const Eigen::Matrix<double, 12, 12> P0 = ekf.covariance();
  ekf.Predict(100.0);
  EXPECT_DOUBLE_EQ(ekf.stamp_s(), 100.0);
  // Grown as for 0.5 s, not 99 s.
  const double dt = 0.5, q = options.accel_noise_mps2 * options.accel_noise_mps2;
  const double sv = options.init_velocity_std_mps;
  EXPECT_NEAR(ekf.covariance()(0, 0), P0(0, 0) + dt * dt * sv * sv + q * dt * dt * dt / 3.0, 1e-9);
}

TEST(PoseEkfTest, NonFiniteMeasurementIsRejected) {
  PoseEkf ekf;
  ekf.Initialize(MovingPose(0.0), 0.0);
  Eigen::Isometry3d bad = MovingPose(0.0);
  bad.translation().y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(ekf.Update(bad, Noise(0.001, 0.01)).accepted);
  EXPECT_TRUE(ekf.fMo().matrix().allFinite());
}

}  // namespace
}  // namespace aerograsp
