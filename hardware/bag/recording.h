// Opens any recording `replay` and `convert` accept, by what the path is:
//   a folder with sequence.yaml      our sequence (hardware/sequence.h)
//   a folder with rgb.txt, depth.txt a TUM RGB-D folder (hardware/tum_folder.h)
//   a .bag file                      a RealSense recording (hardware/bag/realsense_bag.h)
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>

#include "hardware/sequence.h"

namespace aerograsp {

struct RecordingOptions {
  std::string intrinsics_file;           ///< TUM folders: ViSP camera XML or YAML (required)
  std::optional<Eigen::Isometry3d> wMo;  ///< TUM folders: the object in groundtruth.txt's world
  /// .bag and TUM: colour-depth pairing gap, 0 = one depth frame period
  double max_pair_gap_s = 0.0;
};

/// @throws HardwareError / ConfigError naming the path and what is wrong
/// (including what kind of recording it is not, and options that do not apply).
std::unique_ptr<RecordedCamera> OpenRecording(const std::string& path,
                                              const RecordingOptions& options = {});

}  // namespace aerograsp
