// Recorded RGB-D sequences (DESIGN.md, Data formats): a folder with
//   sequence.yaml     intrinsics, depth scale, depth-to-colour transform,
//                     object id, frame rate, frame count
//   color/NNNNNN.png  8-bit RGB
//   depth/NNNNNN.png  16-bit depth in units of depth_scale_m, 0 = no data
//   stamps.csv        frame, stamp_s (optional; else from groundtruth.csv, else frame / rate)
//   groundtruth.csv   optional: frame, stamp_s, cMo as t (m) and q (w, x, y, z)
//   vehicle.csv       optional: frame, stamp_s, wMd as t and q (w, x, y, z), v_w (m/s)
//   joints.csv        optional: frame, stamp_s, left joints (rad), right joints (rad)
// The simulator writes them (`aerograsp record`); ReplayCamera reads them back
// frame by frame, not in real time.
#pragma once

#include <Eigen/Geometry>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "hardware/autopilot.h"
#include "hardware/rgbd_camera.h"

namespace aerograsp {

struct SequenceInfo {
  CameraIntrinsics intrinsics;
  double depth_scale_m = 0.001;
  Eigen::Isometry3d colorMdepth =
      Eigen::Isometry3d::Identity();  ///< identity: depth aligned to colour
  std::string object;                 ///< object id (a shipped name or model path); may be empty
  double frame_rate_hz = 30.0;
  std::int64_t frame_count = 0;
  std::string description;  ///< free text: where it came from (simulator seed, device)
};

/// Per-frame extras a recording may carry.
struct SequenceExtras {
  std::optional<Eigen::Isometry3d> cMo;       ///< ground truth object pose
  std::optional<VehicleState> vehicle;        ///< wMd and v_w
  std::optional<Eigen::VectorXd> q_left_rad;  ///< joints
  std::optional<Eigen::VectorXd> q_right_rad;
};

class SequenceWriter {
 public:
  /// Creates `folder` (and color/, depth/). Refuses a folder that already
  /// holds a sequence.yaml unless `overwrite`.
  /// @throws HardwareError naming the folder.
  SequenceWriter(const std::string& folder, const SequenceInfo& info, bool overwrite = false);
  ~SequenceWriter();
  SequenceWriter(const SequenceWriter&) = delete;
  SequenceWriter& operator=(const SequenceWriter&) = delete;

  /// Writes frame number frame_count() (the frame's own index is ignored).
  /// Extras must be given for every frame or for none, kind by kind.
  /// @throws HardwareError naming the file when it cannot be written or the
  /// images disagree with the intrinsics.
  void Write(const RgbdFrame& frame, const SequenceExtras& extras = {});
  std::int64_t frame_count() const { return count_; }
  /// Writes sequence.yaml (a folder without one is not a sequence). Called by the destructor.
  void Close();

 private:
  std::string folder_;
  SequenceInfo info_;
  std::int64_t count_ = 0;
  bool closed_ = false;
  std::ofstream stamps_, groundtruth_, vehicle_, joints_;
};

/// Reads the sequence.yaml of a folder.
/// @throws HardwareError / ConfigError naming the file and the field.
SequenceInfo ReadSequenceInfo(const std::string& folder);

/// The replay backend of RgbdCamera.
class ReplayCamera : public RgbdCamera {
 public:
  /// Opens and checks the whole folder: sequence.yaml, that every colour and
  /// depth image exists, the optional CSVs (a row per frame, numbers, in order).
  /// Image sizes are checked as each frame is read.
  /// @throws HardwareError naming the file and what is wrong.
  explicit ReplayCamera(const std::string& folder);

  const CameraIntrinsics& intrinsics() const override { return info_.intrinsics; }
  double depth_scale_m() const override { return info_.depth_scale_m; }
  /// Reads the next frame; false after the last one.
  bool Grab(RgbdFrame* frame) override;

  const SequenceInfo& info() const { return info_; }
  const std::string& folder() const { return folder_; }
  /// Extras of frame i (as recorded; empty optionals for what was not).
  const SequenceExtras& extras(std::int64_t i) const {
    return extras_.at(static_cast<std::size_t>(i));
  }
  bool has_groundtruth() const { return has_groundtruth_; }
  /// Goes back to the first frame.
  void Rewind() { next_ = 0; }

 private:
  std::string folder_;
  SequenceInfo info_;
  std::vector<double> stamps_s_;
  std::vector<SequenceExtras> extras_;
  bool has_groundtruth_ = false;
  std::int64_t next_ = 0;
};

}  // namespace aerograsp
