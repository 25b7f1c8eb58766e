// Recorded RGB-D sequences (docs/recordings.md): a folder with
//   sequence.yaml     intrinsics, depth scale, depth-to-colour transform,
//                     object id, frame rate, frame count; optional: the colour
//                     lens model, and the depth camera's own intrinsics and lens
//                     model when the depth images are not aligned to colour
//   color/NNNNNN.png  8-bit RGB
//   depth/NNNNNN.png  16-bit depth in units of depth_scale_m, 0 = no data; the
//                     depth camera's own image when sequence.yaml has depth_camera
//                     (reprojected into the colour camera as it is read, by
//                     AlignDepthToColor), else already aligned to colour
//   stamps.csv        frame, stamp_s (optional; else from groundtruth.csv, else frame / rate)
//   groundtruth.csv   optional: frame, stamp_s, cMo as t (m) and q (w, x, y, z)
//   vehicle.csv       optional: frame, stamp_s, wMd as t and q (w, x, y, z), v_w (m/s)
//   joints.csv        optional: frame, stamp_s, left joints (rad), right joints (rad)
// The simulator writes them (`aerograsp record`), so does `aerograsp convert`
// from other recordings; ReplayCamera reads them back frame by frame, not in real time.
#pragma once

#include <Eigen/Geometry>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hardware/autopilot.h"
#include "hardware/rgbd_alignment.h"
#include "hardware/rgbd_camera.h"

namespace aerograsp {

struct SequenceInfo {
  CameraIntrinsics intrinsics;  ///< of the colour camera (and of the frames' aligned depth)
  DistortionModel color_model = DistortionModel::kNone;  ///< the colour lens
  std::array<double, 5> color_coeffs{};                  ///< k1 k2 p1 p2 k3
  double depth_scale_m = 0.001;
  /// The depth camera when the depth images are its own (unaligned); unset:
  /// the depth images are aligned to colour.
  std::optional<StreamCalibration> depth_camera;
  /// p_color = colorMdepth * p_depth; used with depth_camera.
  Eigen::Isometry3d colorMdepth = Eigen::Isometry3d::Identity();
  std::string object;  ///< object id (a shipped name or model path); may be empty
  double frame_rate_hz = 30.0;
  std::int64_t frame_count = 0;
  std::string description;  ///< free text: where it came from (simulator seed, device)

  /// The colour stream with its lens model.
  StreamCalibration color_stream() const { return {intrinsics, color_model, color_coeffs}; }
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

  /// Writes frame number frame_count() (the frame's own index is ignored); its
  /// stamp must follow the previous frame's.
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
  double last_stamp_s_ = 0.0;
  bool closed_ = false;
  std::ofstream stamps_, groundtruth_, vehicle_, joints_;
};

/// Reads the sequence.yaml of a folder.
/// @throws HardwareError / ConfigError naming the file and the field.
SequenceInfo ReadSequenceInfo(const std::string& folder);

/// A finite recording read frame by frame (`replay` and `convert` take any):
/// a sequence folder, a RealSense .bag, a TUM RGB-D folder. Frames come with
/// depth aligned to colour; info() describes them (no depth_camera).
class RecordedCamera : public RgbdCamera {
 public:
  const CameraIntrinsics& intrinsics() const override { return info().intrinsics; }
  double depth_scale_m() const override { return info().depth_scale_m; }
  /// frame_count is the number of frames Grab() gives.
  virtual const SequenceInfo& info() const = 0;
  /// Extras of frame i (empty optionals for what the recording lacks).
  virtual const SequenceExtras& extras(std::int64_t i) const = 0;
  /// Every frame has its ground-truth cMo.
  virtual bool has_groundtruth() const = 0;
};

/// The replay backend of RgbdCamera.
class ReplayCamera : public RecordedCamera {
 public:
  /// Opens and checks the whole folder: sequence.yaml, that every colour and
  /// depth image exists, the optional CSVs (a row per frame, numbers, in order).
  /// Image sizes are checked as each frame is read.
  /// @throws HardwareError naming the file and what is wrong.
  explicit ReplayCamera(const std::string& folder);

  /// Reads the next frame (depth aligned to colour); false after the last one.
  bool Grab(RgbdFrame* frame) override;

  /// The frames as Grab() gives them: without depth_camera when the folder has one.
  const SequenceInfo& info() const override { return frame_info_; }
  /// sequence.yaml as written.
  const SequenceInfo& stored_info() const { return info_; }
  const std::string& folder() const { return folder_; }
  /// Extras of frame i (as recorded; empty optionals for what was not).
  const SequenceExtras& extras(std::int64_t i) const override {
    return extras_.at(static_cast<std::size_t>(i));
  }
  bool has_groundtruth() const override { return has_groundtruth_; }
  /// Goes back to the first frame.
  void Rewind() { next_ = 0; }

 private:
  std::string folder_;
  SequenceInfo info_, frame_info_;
  std::vector<double> stamps_s_;
  std::vector<SequenceExtras> extras_;
  bool has_groundtruth_ = false;
  std::int64_t next_ = 0;
  std::shared_ptr<const DepthAligner> aligner_;  // with depth_camera, made at the first frame
};

}  // namespace aerograsp
