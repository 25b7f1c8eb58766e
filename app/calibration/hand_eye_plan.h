// The hand-eye wizard's plan: arm poses that show the whole board to the
// camera, clear of the safe volume and of the other arm, shown as a table and
// a picture; and the picture of the solved calibration's poses.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/calibration/calibration_hardware.h"
#include "app/calibration/hand_eye_samples.h"
#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/platform.h"
#include "hardware/rgbd_camera.h"

namespace aerograsp {

/// Joint vectors whose board is in full view, faces the camera and is near,
/// with the arm clear of the safe volume and of the other arm where it is; then
/// a diverse subset (greedy: each next pose the farthest in rotation from
/// those already chosen).
std::vector<Eigen::VectorXd> PlanPoses(const Platform& platform, Side side,
                                       const TagBoardConfig& board, const Eigen::Isometry3d& eMt,
                                       const Eigen::VectorXd& other_q, int count,
                                       std::uint64_t seed);
/// The planned poses: joints, where the board would be and how it would face
/// the camera, as a table; and the boards' outlines over the pre-flight frame.
void ShowPlan(const std::vector<Eigen::VectorXd>& poses, const Platform& platform, Side side,
              const CalibrationRig& rig, const RgbdFrame& frame, const std::string& picture,
              std::ostream& out);
/// Outlines of the board as measured (green) and as the calibration predicts
/// (red) for every accepted sample, over the first accepted image.
void DrawPoses(const std::string& folder, const std::vector<WizardSample>& samples,
               const TagBoardConfig& board, const CameraIntrinsics& K,
               const HandEyeResult& solution);

}  // namespace aerograsp
