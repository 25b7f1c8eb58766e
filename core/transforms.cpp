#include "core/transforms.h"

#include <algorithm>
#include <cmath>

namespace aerograsp {

Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy_rad) {
  return (Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R) {
  // R = Rz(y) Ry(p) Rx(r): R(2,0) = -sin(p), R(2,1) = cos(p) sin(r), R(2,2) = cos(p) cos(r),
  // R(1,0) = sin(y) cos(p), R(0,0) = cos(y) cos(p).
  const double sp = std::clamp(-R(2, 0), -1.0, 1.0);
  if (std::abs(sp) > 1.0 - 1e-12) {
    // Gimbal lock (asin is ill-conditioned here, so pitch is set exactly): only
    // yaw - sign(p) * roll is observable; put it all in yaw.
    const double yaw = std::atan2(-R(0, 1), R(1, 1));
    return {0.0, std::copysign(M_PI / 2, sp), yaw};
  }
  return {std::atan2(R(2, 1), R(2, 2)), std::asin(sp), std::atan2(R(1, 0), R(0, 0))};
}

Eigen::Isometry3d MakeTransform(const Eigen::Vector3d& xyz_m, const Eigen::Vector3d& rpy_rad) {
  Eigen::Isometry3d aMb = Eigen::Isometry3d::Identity();
  aMb.linear() = RotationFromRpy(rpy_rad);
  aMb.translation() = xyz_m;
  return aMb;
}

Eigen::Isometry3d MakeTransformWxyz(const Eigen::Vector3d& xyz_m, const Eigen::Vector4d& q_wxyz) {
  Eigen::Quaterniond q(q_wxyz[0], q_wxyz[1], q_wxyz[2], q_wxyz[3]);
  q.normalize();
  Eigen::Isometry3d aMb = Eigen::Isometry3d::Identity();
  aMb.linear() = q.toRotationMatrix();
  aMb.translation() = xyz_m;
  return aMb;
}

Eigen::Vector4d QuaternionWxyz(const Eigen::Isometry3d& aMb) {
  Eigen::Quaterniond q(aMb.rotation());
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return {q.w(), q.x(), q.y(), q.z()};
}

Eigen::Vector3d ThetaU(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}

double RotationAngle(const Eigen::Matrix3d& R) {
  // atan2 of |sin| and cos is accurate at both ends, unlike acos of the trace.
  const Eigen::Vector3d v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const double sin_theta = 0.5 * v.norm();
  const double cos_theta = 0.5 * (R.trace() - 1.0);
  return std::atan2(sin_theta, cos_theta);
}

PoseError ComparePoses(const Eigen::Isometry3d& aMb_1, const Eigen::Isometry3d& aMb_2) {
  const Eigen::Isometry3d b1Mb2 = aMb_1.inverse() * aMb_2;
  return {b1Mb2.translation().norm(), RotationAngle(b1Mb2.linear())};
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

bool IsValidTransform(const Eigen::Isometry3d& aMb, double tolerance) {
  if (!aMb.matrix().allFinite()) return false;
  const Eigen::Matrix3d R = aMb.linear();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < tolerance &&
         std::abs(R.determinant() - 1.0) < tolerance;
}

}  // namespace aerograsp
