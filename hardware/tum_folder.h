// Folders in the TUM RGB-D benchmark's layout as a recorded camera:
//   rgb.txt, depth.txt   "timestamp filename" per line ('#' starts a comment),
//                        timestamps in seconds, file names relative to the folder
//   rgb/*.png            8-bit colour
//   depth/*.png          16-bit depth, 5000 units per metre, 0 = no data,
//                        registered to the colour camera
//   groundtruth.txt      optional: "timestamp tx ty tz qx qy qz qw", the camera
//                        in the world (wMc)
// The folders carry no intrinsics: they come from a ViSP camera XML or a YAML
// file. Each colour frame is paired with the depth frame nearest in time
// (PairByStamp); colour frames without a depth frame close enough are skipped.
// With the object's pose in TUM's world (wMo), the ground truth gives each
// frame its cMo = wMc^-1 wMo, wMc interpolated at the colour stamp.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "hardware/sequence.h"

namespace aerograsp {

/// Depth units of the TUM layout: 5000 per metre.
constexpr double kTumDepthScaleM = 1.0 / 5000.0;

/// Intrinsics from a ViSP camera XML (.xml) or a YAML file (.yaml, .yml) with
/// width, height, fx, fy, cx, cy at the top level or under `intrinsics:` (a
/// sequence.yaml will do).
/// @throws ConfigError naming the file.
CameraIntrinsics LoadIntrinsicsFile(const std::string& path);

/// A folder holding rgb.txt and depth.txt.
bool IsTumFolder(const std::string& folder);

struct TumOptions {
  std::optional<CameraIntrinsics> intrinsics;  ///< required
  std::optional<Eigen::Isometry3d> wMo;        ///< the object in groundtruth.txt's world
  double max_pair_gap_s = 0.0;                 ///< 0: one depth frame period
  std::string object;                          ///< object id recorded in info()
};

class TumCamera : public RecordedCamera {
 public:
  /// Reads the lists (and groundtruth.txt) and pairs the frames; images are read by Grab().
  /// @throws HardwareError naming the file and line (missing intrinsics, a
  /// malformed line, a listed image that does not exist, no frame paired).
  TumCamera(const std::string& folder, const TumOptions& options);

  bool Grab(RgbdFrame* frame) override;
  const SequenceInfo& info() const override { return info_; }
  const SequenceExtras& extras(std::int64_t i) const override {
    return extras_.at(static_cast<std::size_t>(i));
  }
  bool has_groundtruth() const override { return has_groundtruth_; }
  /// Colour frames left out: no depth frame within the pairing gap.
  int unpaired_frames() const { return unpaired_; }

 private:
  std::string folder_;
  SequenceInfo info_;
  std::vector<std::string> color_files_, depth_files_;  // per paired frame
  std::vector<double> stamps_s_;
  std::vector<SequenceExtras> extras_;
  bool has_groundtruth_ = false;
  int unpaired_ = 0;
  std::int64_t next_ = 0;
};

}  // namespace aerograsp
