// The hand-eye wizard's samples (joints, the board's pose and corners, the
// image) and their file, DIR/samples.yaml, which `calibrate --resolve DIR`
// solves again. yaml-cpp stays in the .cpp file.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/platform.h"

namespace aerograsp {

/// One sample of the hand-eye wizard.
struct WizardSample {
  std::string image;  ///< relative to the output folder
  Eigen::VectorXd q_rad;
  bool accepted = false;
  std::string reject_reason;
  HandEyeSample data;  ///< bMe, cMt, corners
};

/// "left" | "right". @throws ConfigError "--arm: '<arm>' is not left or right".
Side ParseSide(const std::string& arm);

/// Writes the samples with the platform file, the arm and the board.
/// @throws std::runtime_error naming the file when it cannot be written.
void WriteSamplesYaml(const std::string& path, const std::string& platform_path, Side side,
                      const TagBoardConfig& board, const std::vector<WizardSample>& samples);

/// Reads WriteSamplesYaml's file (bMe from the joints through the platform's arm).
/// @throws ConfigError "<file>: <key>: ..." for a malformed entry.
std::vector<WizardSample> ReadSamplesYaml(const std::string& path, std::string* platform_path,
                                          Side* side, TagBoardConfig* board);

}  // namespace aerograsp
