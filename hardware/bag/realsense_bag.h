// RealSense recordings (.bag, written by realsense-viewer and rs-record) read
// with ROS 1's bag library, no librealsense. The layout librealsense's recorder
// writes (file versions 2 to 4):
//   /file_version                                 std_msgs/UInt32
//   /device_D/sensor_S/Depth_N/image/data          sensor_msgs/Image (mono16 / 16UC1)
//   /device_D/sensor_S/Color_N/image/data          sensor_msgs/Image (rgb8, bgr8, rgba8, bgra8)
//   .../<stream>/info/camera_info                  sensor_msgs/CameraInfo: size, K, lens model, D
//   .../<stream>/tf/0                              geometry_msgs/Transform: the stream's extrinsic
//                                                  from the reference stream (p_stream = T p_ref)
//   /device_D/sensor_S/option/Depth Units/value    std_msgs/Float32, metres per depth unit
// realsense_msgs/StreamInfo and the diagnostic_msgs/KeyValue metadata are not needed.
// Frames are paired by the bag's record time (one clock for all sensors): each
// colour frame with the nearest depth frame (PairByStamp); the depth is
// reprojected into the colour camera (AlignDepthToColor). ROS stays in the .cpp.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "hardware/rgbd_alignment.h"
#include "hardware/sequence.h"

namespace aerograsp {

struct BagOptions {
  double max_pair_gap_s = 0.0;  ///< 0: one depth frame period
  std::string object;           ///< object id recorded in info()
};

class RealsenseBagCamera : public RecordedCamera {
 public:
  /// Opens the bag and checks it: a colour and a depth stream with their
  /// camera_info, the extrinsic, a supported lens model, the first image of
  /// each stream of the size its camera_info says.
  /// @throws HardwareError naming the file (and topic) and what is wrong.
  RealsenseBagCamera(const std::string& path, const BagOptions& options = {});
  ~RealsenseBagCamera() override;

  /// The next colour frame with its paired depth aligned to colour.
  /// @throws HardwareError naming the file, topic and message when an image
  /// cannot be read or has another size or encoding.
  bool Grab(RgbdFrame* frame) override;
  const SequenceInfo& info() const override;
  const SequenceExtras& extras(std::int64_t i) const override;
  bool has_groundtruth() const override { return false; }

  const StreamCalibration& color_stream() const;
  const StreamCalibration& depth_stream() const;
  /// p_color = colorMdepth * p_depth
  const Eigen::Isometry3d& colorMdepth() const;
  /// Depth image of the last Grab() as recorded (the depth camera's own).
  const DepthImage& last_raw_depth() const;
  int file_version() const;
  /// Colour frames left out (no depth frame within the gap) and the gap used (s).
  int unpaired_frames() const;
  double pairing_gap_s() const;
  /// Largest |colour - depth| record-time difference among the pairs (s).
  double max_pair_offset_s() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes a bag in the layout above (file version 4, device 0, depth on
/// sensor 0, colour on sensor 1), e.g. a simulated recording for tests.
class RealsenseBagWriter {
 public:
  struct Streams {
    StreamCalibration color, depth;
    Eigen::Isometry3d colorMdepth = Eigen::Isometry3d::Identity();
    double depth_scale_m = 0.001;
    /// Lens model names as written in the camera_info ("" = from the models).
    std::string color_model_name, depth_model_name;
  };
  /// @throws HardwareError naming the file when it cannot be created.
  RealsenseBagWriter(const std::string& path, const Streams& streams);
  ~RealsenseBagWriter();
  RealsenseBagWriter(const RealsenseBagWriter&) = delete;
  RealsenseBagWriter& operator=(const RealsenseBagWriter&) = delete;

  /// Images at record time `stamp_s` (> 0), written as they are (no check of their size).
  void WriteColor(double stamp_s, const ColorImage& color);
  void WriteDepth(double stamp_s, const DepthImage& depth);
  void Close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aerograsp
