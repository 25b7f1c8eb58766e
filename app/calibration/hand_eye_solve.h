// Solving the hand-eye calibration: from the wizard's samples (the
// calibration the mission loads, its URDF and tf forms, summary.json and
// poses.png) and from a data set in ViSP's convention (`calibrate --resolve DIR`).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/calibration/calibration_visp.h"
#include "app/calibration/hand_eye_samples.h"
#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/platform.h"

namespace aerograsp {

/// Solves from the accepted samples, prints the comparison, writes the
/// calibration YAML, summary.json and poses.png.
void SolveHandEyeAndReport(const std::string& folder, const std::string& platform_path, Side side,
                           const TagBoardConfig& board, const std::vector<WizardSample>& samples,
                           const std::optional<Eigen::Isometry3d>& truth_cMb, std::ostream& out);
/// `--resolve DIR` on a data set in ViSP's convention (app/calibration/calibration_visp.h):
/// ViSP's solver (what visp-compute-eye-to-hand-calibration /
/// visp-compute-eye-in-hand-calibration give) and OpenCV's five for
/// comparison; writes the result as ViSP pose files (rPc.yaml and ePo.yaml
/// eye-to-hand, eMc.yaml and rPo.yaml eye-in-hand), a URDF joint, the
/// static_transform_publisher command and summary.json in `out_folder`.
void ResolveVispDataset(const std::string& folder, HandEyeSetup setup, double tag_size_m,
                        const std::string& out_folder, std::ostream& out);

}  // namespace aerograsp
