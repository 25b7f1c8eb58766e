#include "detection/pose_ekf.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/transforms.h"

namespace aerograsp {
namespace {

Eigen::Matrix3d ExpSo3(const Eigen::Vector3d& theta) {
  const double angle = theta.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity() + Skew(theta);
  return Eigen::AngleAxisd(angle, theta / angle).toRotationMatrix();
}

}  // namespace

void PoseEkf::Initialize(const Eigen::Isometry3d& fMo, double stamp_s) {
  p_f_ = fMo.translation();
  fRo_ = fMo.linear();
  v_f_.setZero();
  w_f_.setZero();
  stamp_s_ = stamp_s;
  P_.setZero();
  P_.diagonal() << Eigen::Vector3d::Constant(options_.init_position_std_m *
                                             options_.init_position_std_m),
      Eigen::Vector3d::Constant(options_.init_rotation_std_rad * options_.init_rotation_std_rad),
      Eigen::Vector3d::Constant(options_.init_velocity_std_mps * options_.init_velocity_std_mps),
      Eigen::Vector3d::Constant(options_.init_angular_velocity_std_radps *
                                options_.init_angular_velocity_std_radps);
  initialized_ = true;
}

void PoseEkf::Predict(double stamp_s) {
  if (!initialized_ || !(stamp_s > stamp_s_)) return;
  const double dt = std::min(stamp_s - stamp_s_, options_.max_predict_dt_s);
  stamp_s_ = stamp_s;
  p_f_ += v_f_ * dt;
  fRo_ = ExpSo3(w_f_ * dt) * fRo_;
  Eigen::Matrix<double, 12, 12> F = Eigen::Matrix<double, 12, 12>::Identity();
  F.block<3, 3>(0, 6) = Eigen::Matrix3d::Identity() * dt;
  F.block<3, 3>(3, 9) = Eigen::Matrix3d::Identity() * dt;
  Eigen::Matrix<double, 12, 12> Q = Eigen::Matrix<double, 12, 12>::Zero();
  const double qa = options_.accel_noise_mps2 * options_.accel_noise_mps2;
  const double qw = options_.angular_accel_noise_radps2 * options_.angular_accel_noise_radps2;
  for (int k = 0; k < 2; ++k) {
    const double q = k == 0 ? qa : qw;
    const int pos = 3 * k, vel = 6 + 3 * k;
    Q.block<3, 3>(pos, pos) = Eigen::Matrix3d::Identity() * q * dt * dt * dt / 3.0;
    Q.block<3, 3>(pos, vel) = Eigen::Matrix3d::Identity() * q * dt * dt / 2.0;
    Q.block<3, 3>(vel, pos) = Eigen::Matrix3d::Identity() * q * dt * dt / 2.0;
    Q.block<3, 3>(vel, vel) = Eigen::Matrix3d::Identity() * q * dt;
  }
  P_ = F * P_ * F.transpose() + Q;
}

EkfUpdate PoseEkf::Innovation(const Eigen::Isometry3d& fMo_meas,
                              const Eigen::Matrix<double, 6, 6>& R) const {
  EkfUpdate out;
  if (!initialized_ || !fMo_meas.matrix().allFinite()) return out;
  Eigen::Matrix<double, 6, 1> y;
  y.head<3>() = fMo_meas.translation() - p_f_;
  y.tail<3>() = ThetaU(fMo_meas.linear() * fRo_.transpose());
  const Eigen::Matrix<double, 6, 6> S = P_.topLeftCorner<6, 6>() + R;
  out.nis = y.dot(S.ldlt().solve(y));
  out.accepted = std::isfinite(out.nis) && out.nis <= options_.gate_nis;
  return out;
}

EkfUpdate PoseEkf::Update(const Eigen::Isometry3d& fMo_meas, const Eigen::Matrix<double, 6, 6>& R) {
  const EkfUpdate out = Innovation(fMo_meas, R);
  if (!out.accepted) return out;
  Eigen::Matrix<double, 6, 1> y;
  y.head<3>() = fMo_meas.translation() - p_f_;
  y.tail<3>() = ThetaU(fMo_meas.linear() * fRo_.transpose());
  const Eigen::Matrix<double, 6, 6> S = P_.topLeftCorner<6, 6>() + R;
  const Eigen::Matrix<double, 12, 6> K = P_.leftCols<6>() * S.inverse();
  const Eigen::Matrix<double, 12, 1> dx = K * y;
  p_f_ += dx.segment<3>(0);
  fRo_ = ExpSo3(dx.segment<3>(3)) * fRo_;
  fRo_ = Eigen::Quaterniond(fRo_).normalized().toRotationMatrix();
  v_f_ += dx.segment<3>(6);
  w_f_ += dx.segment<3>(9);
  Eigen::Matrix<double, 12, 12> IKH = Eigen::Matrix<double, 12, 12>::Identity();
  IKH.leftCols<6>() -= K;
  P_ = IKH * P_ * IKH.transpose() + K * R * K.transpose();
  return out;
}

Eigen::Isometry3d PoseEkf::fMo() const {
  Eigen::Isometry3d fMo = Eigen::Isometry3d::Identity();
  fMo.linear() = fRo_;
  fMo.translation() = p_f_;
  return fMo;
}

}  // namespace aerograsp
