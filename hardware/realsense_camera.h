// The Intel RealSense D435 backend of RgbdCamera (built only when
// librealsense2 is found at configure time; it is not in Debian, see README):
// colour RGB8 and depth Z16, depth aligned to colour by librealsense's
// rs2::align, intrinsics of the colour stream. The same class replays .bag
// recordings (ROS 1 bag format, as realsense-viewer writes them) through
// librealsense's own reader, frame by frame (not in real time), into the same
// RgbdFrame as the sequence folders' ReplayCamera.
#pragma once

#include <memory>
#include <string>

#include "hardware/rgbd_camera.h"

namespace aerograsp {

struct RealSenseOptions {
  std::string serial;    ///< device serial number; empty = the first device
  std::string bag_path;  ///< non-empty: replay this .bag instead of a device
  int width = 640;       ///< pixels (live devices; a bag has its own)
  int height = 480;
  int fps = 30;
  int timeout_ms = 2000;  ///< wait for a frame set
};

class RealSenseCamera : public RgbdCamera {
 public:
  /// Starts the pipeline.
  /// @throws HardwareError "camera: RealSense <serial>: ..." or "camera: <bag>: ..."
  /// when no device answers, the streams cannot be configured or the file cannot be read.
  explicit RealSenseCamera(const RealSenseOptions& options);
  ~RealSenseCamera() override;
  RealSenseCamera(const RealSenseCamera&) = delete;
  RealSenseCamera& operator=(const RealSenseCamera&) = delete;

  const CameraIntrinsics& intrinsics() const override { return intrinsics_; }
  double depth_scale_m() const override { return depth_scale_m_; }
  /// Next aligned frame; false at the end of a bag.
  /// @throws HardwareError when a live device stops delivering frames.
  bool Grab(RgbdFrame* frame) override;

 private:
  struct State;  // librealsense objects (kept out of this header)
  std::unique_ptr<State> state_;
  RealSenseOptions options_;
  std::string name_;  // for messages
  CameraIntrinsics intrinsics_;
  double depth_scale_m_ = 0.001;
  std::int64_t next_index_ = 0;
};

}  // namespace aerograsp
