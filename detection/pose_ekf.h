// Extended Kalman filter on the object's pose in the camera frame with a
// constant-velocity model (paper Sect. 3: "a simple kinematic model").
// State: position p (m) and rotation cRo of the object in c, linear velocity
// v (m/s) and angular velocity w (rad/s), both expressed in c. The covariance
// is kept on the 12-D error state [dp, dtheta, dv, dw] with the rotation error
// on the left: cRo = Exp(dtheta) * cRo_hat. Measurements are full poses cMo
// (from ICP); an innovation whose Mahalanobis distance exceeds the gate is
// rejected as an outlier and leaves the state untouched.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace aerograsp {

struct PoseEkfOptions {
  double accel_noise_mps2 = 2.0;  ///< white linear acceleration density (sigma over 1 s), > 0
  double angular_accel_noise_radps2 = 4.0;  ///< white angular acceleration density, > 0
  double init_position_std_m = 0.01;        ///< prior of a fresh track
  double init_rotation_std_rad = 0.05;
  double init_velocity_std_mps = 0.2;
  double init_angular_velocity_std_radps = 0.5;
  double gate_nis = 22.46;  ///< chi-square 6 dof at 99.9 %: innovations beyond it are outliers
  double max_predict_dt_s =
      1.0;  ///< longer gaps predict over this at most (a stale velocity must not run away)
};

/// The innovation of one update.
struct EkfUpdate {
  bool accepted = false;
  double nis = 0.0;  ///< normalised innovation squared y^T S^-1 y
};

class PoseEkf {
 public:
  explicit PoseEkf(const PoseEkfOptions& options = {}) : options_(options) {}

  /// Starts a track at cMo with zero velocity and the prior covariance.
  void Initialize(const Eigen::Isometry3d& cMo, double stamp_s);
  bool initialized() const { return initialized_; }
  void Reset() { initialized_ = false; }

  /// Propagates the state to stamp_s (no-op for stamp_s <= the current stamp).
  void Predict(double stamp_s);
  /// The innovation of a measurement without applying it.
  EkfUpdate Innovation(const Eigen::Isometry3d& cMo_meas,
                       const Eigen::Matrix<double, 6, 6>& R) const;
  /// Fuses a measured cMo with covariance R (position m^2, then rotation rad^2,
  /// rotation error on the left). Gated measurements are not applied.
  EkfUpdate Update(const Eigen::Isometry3d& cMo_meas, const Eigen::Matrix<double, 6, 6>& R);

  Eigen::Isometry3d cMo() const;
  const Eigen::Vector3d& v_c() const { return v_; }
  const Eigen::Vector3d& w_c() const { return w_; }
  double stamp_s() const { return stamp_s_; }
  /// 12x12 error-state covariance [dp, dtheta, dv, dw].
  const Eigen::Matrix<double, 12, 12>& covariance() const { return P_; }

 private:
  PoseEkfOptions options_;
  bool initialized_ = false;
  double stamp_s_ = 0.0;
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero(), v_ = Eigen::Vector3d::Zero(),
                  w_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 12, 12> P_ = Eigen::Matrix<double, 12, 12>::Identity();
};

}  // namespace aerograsp
