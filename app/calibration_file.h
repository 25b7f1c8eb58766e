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

}  // namespace aerograsp
