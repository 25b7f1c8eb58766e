// Extended Kalman filter on the object's pose in a filter frame f with a
// constant-velocity model (paper Sect. 3: "a simple kinematic model"). f is
// the caller's choice; the model holds best in a frame that does not move: the
// object tracker runs the filter in the world (f = w) whenever it is given the
// camera's pose, and in the camera (f = c) only when it is not.
// State: position p_f (m) and rotation fRo of the object in f, linear velocity
// v_f (m/s) and angular velocity w_f (rad/s), both expressed in f. The
// covariance is kept on the 12-D error state [dp, dtheta, dv, dw] with the
// rotation error on the left: fRo = Exp(dtheta) * fRo_hat. Measurements are
// full poses fMo (from ICP); an innovation whose Mahalanobis distance exceeds
// the gate is rejected as an outlier and leaves the state untouched.
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
  /// Longer gaps predict over this at most (a stale velocity must not run away), s.
  double max_predict_dt_s = 1.0;
};

/// The innovation of one update.
struct EkfUpdate {
  bool accepted = false;
  double nis = 0.0;  ///< normalised innovation squared y^T S^-1 y
};

class PoseEkf {
 public:
  explicit PoseEkf(const PoseEkfOptions& options = {}) : options_(options) {}

  /// Starts a track at fMo with zero velocity and the prior covariance.
  void Initialize(const Eigen::Isometry3d& fMo, double stamp_s);
  bool initialized() const { return initialized_; }
  void Reset() { initialized_ = false; }

  /// Propagates the state to stamp_s (no-op for stamp_s <= the current stamp).
  void Predict(double stamp_s);
  /// The innovation of a measurement without applying it.
  EkfUpdate Innovation(const Eigen::Isometry3d& fMo_meas,
                       const Eigen::Matrix<double, 6, 6>& R) const;
  /// Fuses a measured fMo with covariance R (position m^2, then rotation rad^2,
  /// rotation error on the left). Gated measurements are not applied.
  EkfUpdate Update(const Eigen::Isometry3d& fMo_meas, const Eigen::Matrix<double, 6, 6>& R);

  /// The object's pose in the filter frame f.
  Eigen::Isometry3d fMo() const;
  /// The object's linear (m/s) and angular (rad/s) velocity, expressed in f.
  const Eigen::Vector3d& v_f() const { return v_f_; }
  const Eigen::Vector3d& w_f() const { return w_f_; }
  double stamp_s() const { return stamp_s_; }
  /// 12x12 error-state covariance [dp, dtheta, dv, dw].
  const Eigen::Matrix<double, 12, 12>& covariance() const { return P_; }

 private:
  PoseEkfOptions options_;
  bool initialized_ = false;
  double stamp_s_ = 0.0;
  Eigen::Vector3d p_f_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_f_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_f_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d fRo_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 12, 12> P_ = Eigen::Matrix<double, 12, 12>::Identity();
};

}  // namespace aerograsp
