// The camera-to-arm-base transform of an arm (eye-to-hand: camera and arm base
// both fixed on the vehicle) from views of a tag board carried by the gripper.
//
// Each sample i gives bMe_i (forward kinematics) and cMt_i (board pose).
// Unknowns: cMb (what the mission needs) and eMt (where the board sits on the
// gripper). Model: cMt_i = cMb * bMe_i * eMt. Rewritten as
// eMb_i * bMc * cMt_i = eMt (constant), it is the classic AX = XB problem
// with "robot" poses eMb_i = bMe_i^-1, solved by ViSP's vpHandEyeCalibration
// and by OpenCV's calibrateHandEye, then refined on the board corners'
// reprojection error (Levenberg-Marquardt over both transforms).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "core/camera_model.h"

namespace aerograsp {

struct HandEyeSample {
  Eigen::Isometry3d bMe = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d cMt = Eigen::Isometry3d::Identity();
  /// Board corners seen in this sample: (point in t, pixel). Optional; used by the refinement.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector2d>> corners;
};

struct HandEyeResult {
  std::string method;  ///< "visp", "opencv-tsai", ..., "refined"
  bool ok = false;
  std::string message;  ///< why it failed
  Eigen::Isometry3d cMb = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d eMt = Eigen::Isometry3d::Identity();
  std::vector<double> residual_mm, residual_deg;  ///< per sample: predicted vs measured cMt
  double residual_mm_rms = 0.0, residual_deg_rms = 0.0;
  double reprojection_rms_px = 0.0;  ///< over all corners, when the samples carry them
};

/// How varied the samples' gripper orientations are: the largest rotation
/// between two samples, and the rank of the set of relative rotation axes
/// (rank < 2 makes the rotation part singular).
struct PoseSetDiversity {
  double max_rotation_deg = 0.0;
  int axis_rank = 0;
  /// The tool-frame axis the samples rotate least about (unit; meaningful with 2+ samples).
  Eigen::Vector3d least_axis_e = Eigen::Vector3d::UnitZ();
  bool Sufficient() const { return axis_rank >= 2 && max_rotation_deg >= 20.0; }
};
PoseSetDiversity MeasureDiversity(const std::vector<HandEyeSample>& samples);

/// What the next sample should add, for a person placing the arm: "" when the
/// set is diverse (rotations about all three tool axes, 20 deg or more apart),
/// else e.g. "rotate the gripper more about its approach axis (z)".
std::string DiversityAdvice(const PoseSetDiversity& diversity, std::size_t samples);

/// ViSP's vpHandEyeCalibration (Tsai/Procrustes then virtual visual servoing).
HandEyeResult SolveEyeToHandVisp(const std::vector<HandEyeSample>& samples,
                                 const CameraIntrinsics& K);

/// OpenCV's calibrateHandEye with each of its five methods.
std::vector<HandEyeResult> SolveEyeToHandOpenCv(const std::vector<HandEyeSample>& samples,
                                                const CameraIntrinsics& K);

/// Levenberg-Marquardt on the reprojection error of every sample's corners,
/// over cMb and eMt, from `initial`. Needs samples with corners.
HandEyeResult RefineEyeToHand(const std::vector<HandEyeSample>& samples, const CameraIntrinsics& K,
                              const HandEyeResult& initial);

}  // namespace aerograsp
