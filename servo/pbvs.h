// Position-based visual servoing of an end effector with ViSP's vpServo: the
// features are the translation and theta-u of gMe (the current end effector e
// seen from the desired pose g), driven to zero. The camera is fixed on the
// vehicle, so "visual" means the target gMe comes from vision and the planner;
// e comes from kinematics.
#pragma once

#include <Eigen/Geometry>
#include <memory>

namespace aerograsp {

class PbvsTask {
 public:
  /// @param gain_per_s exponential decrease rate of the error (lambda, 1/s), > 0.
  explicit PbvsTask(double gain_per_s);
  ~PbvsTask();
  PbvsTask(PbvsTask&&) noexcept;
  PbvsTask& operator=(PbvsTask&&) noexcept;
  PbvsTask(const PbvsTask&) = delete;
  PbvsTask& operator=(const PbvsTask&) = delete;

  /// The end effector's desired twist, expressed in the arm base b:
  /// (v_x, v_y, v_z, w_x, w_y, w_z) with v the velocity of e's origin (m/s) and w
  /// the angular velocity (rad/s), from vpServo's control law v_e = -lambda L^+ e.
  /// bMe and bMg must be valid rigid transforms.
  Eigen::Matrix<double, 6, 1> Twist(const Eigen::Isometry3d& bMe, const Eigen::Isometry3d& bMg);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aerograsp
