// Rigid transforms with Eigen. Poses are Eigen::Isometry3d named `aMb` (frame b
// expressed in frame a, see core/frames.h). Conversions to ViSP and PCL types
// live in core/conversions.h.
#pragma once

#include <Eigen/Geometry>

namespace aerograsp {

/// Rotation from roll, pitch, yaw (rad) as URDF defines them: fixed-axis
/// rotations about x, then y, then z, i.e. R = Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d RotationFromRpy(const Eigen::Vector3d& rpy_rad);

/// Inverse of RotationFromRpy; pitch in [-pi/2, pi/2]. At pitch = +-pi/2 roll is
/// returned as 0 and yaw carries the remaining rotation.
Eigen::Vector3d RpyFromRotation(const Eigen::Matrix3d& R);

/// aMb from a translation (m) and roll-pitch-yaw (rad), URDF convention.
Eigen::Isometry3d MakeTransform(const Eigen::Vector3d& xyz_m, const Eigen::Vector3d& rpy_rad);

/// aMb from a translation (m) and a unit quaternion given as (w, x, y, z).
/// The quaternion is normalised; a zero quaternion is a precondition violation.
Eigen::Isometry3d MakeTransformWxyz(const Eigen::Vector3d& xyz_m, const Eigen::Vector4d& q_wxyz);

/// The quaternion of a transform's rotation as (w, x, y, z), with w >= 0.
Eigen::Vector4d QuaternionWxyz(const Eigen::Isometry3d& aMb);

/// The theta-u (axis times angle, rad) vector of a rotation, angle in [0, pi].
Eigen::Vector3d ThetaU(const Eigen::Matrix3d& R);

/// Rotation angle (rad, in [0, pi]) of a rotation matrix; robust near 0 and pi.
double RotationAngle(const Eigen::Matrix3d& R);

/// Pose difference between two estimates of the same transform: translation
/// distance (m) and rotation angle (rad) of aMb_1^-1 * aMb_2.
struct PoseError {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};
PoseError ComparePoses(const Eigen::Isometry3d& aMb_1, const Eigen::Isometry3d& aMb_2);

/// Skew-symmetric matrix [v]x such that [v]x * w = v x w.
Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

/// True when every coefficient is finite and the rotation part is orthonormal
/// with determinant +1 within `tolerance`.
bool IsValidTransform(const Eigen::Isometry3d& aMb, double tolerance = 1e-6);

}  // namespace aerograsp
