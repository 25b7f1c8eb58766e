// The camera-to-arm calibration file that `aerograsp calibrate` writes
// (DIR/calibration_<arm>.yaml) and the mission loads: the arm base in the
// camera frame cMb (what the hand-eye solve measures), dMb through the
// platform's nominal dMc, where the board sat on the gripper (eMt), the
// residuals and the samples' file. Matrices are 16 numbers, row by row.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/platform.h"

namespace aerograsp {

struct ArmCalibration {
  std::string source;  ///< the file (for messages)
  Side side = Side::kLeft;
  std::string method;  ///< the solver whose result this is ("refined", "visp", ...)
  Eigen::Isometry3d cMb = Eigen::Isometry3d::Identity();  ///< the arm base in the camera frame
  Eigen::Isometry3d dMb = Eigen::Isometry3d::Identity();  ///< the same through the nominal dMc
  Eigen::Isometry3d eMt = Eigen::Isometry3d::Identity();  ///< the board on the gripper
  double residual_mm = 0.0, residual_deg = 0.0;
  std::string samples{"samples.yaml"};  ///< relative to the file's folder

  /// @throws ConfigError "<file>: <key>: ..." for a missing or malformed file,
  /// an unknown arm, or a matrix that is not 16 numbers of a rigid transform.
  static ArmCalibration Load(const std::string& path);
  /// @throws std::runtime_error naming the file when it cannot be written.
  void Write(const std::string& path) const;
};

/// The 16 numbers of aMb's 4x4 matrix, row by row (as the calibration files hold them).
std::vector<double> FlattenRowMajor(const Eigen::Isometry3d& aMb);

/// A fixed URDF joint that places `child` at parentMchild in `parent`:
/// `<joint name type="fixed"><parent/><child/><origin xyz rpy/></joint>`, rpy as
/// URDF defines it (fixed axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll)), metres
/// and radians with every digit a double needs.
std::string UrdfFixedJoint(const std::string& joint, const std::string& parent,
                           const std::string& child, const Eigen::Isometry3d& parentMchild);

/// The arguments of ROS 2's `ros2 run tf2_ros static_transform_publisher` for
/// the same transform: `--x --y --z --qx --qy --qz --qw --frame-id parent
/// --child-frame-id child`.
std::string StaticTransformPublisherArgs(const std::string& parent, const std::string& child,
                                         const Eigen::Isometry3d& parentMchild);

/// Writes `<stem>.urdf` (the joint, with a comment naming both frames) and
/// `<stem>_tf.sh` (the static_transform_publisher command) in `folder`.
/// @throws std::runtime_error naming the file when it cannot be written.
void WriteRosFrames(const std::string& folder, const std::string& stem, const std::string& parent,
                    const std::string& child, const Eigen::Isometry3d& parentMchild,
                    const std::string& comment);

/// The frame names of data/robots/vehicle.urdf that an arm's calibration
/// relates: the camera's optical frame (z forward, x right, y down) and the
/// arm's base (its mount on the body).
constexpr const char* kCameraOpticalFrame = "camera_optical";
std::string ArmBaseFrame(Side side);

}  // namespace aerograsp
