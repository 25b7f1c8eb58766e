// Depth from its own camera made usable as the RgbdFrame contract wants it:
// reprojected into the colour camera (spatial alignment) and paired with the
// colour frame nearest in time (temporal pairing). One implementation for
// every input: RealSense .bag files, sequences with unaligned depth, TUM folders.
//
// Lens models follow librealsense's names (doc/projection.md there):
//   none                    pinhole
//   Brown Conrady           OpenCV's k1 k2 p1 p2 k3 ("plumb_bob" in ROS), forward
//                           (undistorted -> distorted) in closed form
//   Modified Brown Conrady  the same, with the tangential terms applied to the
//                           radially distorted point, forward in closed form
//   Inverse Brown Conrady   the Brown Conrady polynomial maps distorted to
//                           undistorted points (closed-form deprojection)
// The other direction of each model is solved by Newton iterations.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/image.h"

namespace aerograsp {

enum class DistortionModel { kNone, kBrownConrady, kModifiedBrownConrady, kInverseBrownConrady };

/// The model's name as written in files ("none", "Brown Conrady", ...).
std::string ToString(DistortionModel model);
/// Parses a model name: the names above (case-insensitive), "plumb_bob" and
/// "radtan" (Brown Conrady) and "" (none).
/// @throws HardwareError "<source>: distortion model '<name>' is not supported (...)".
DistortionModel ParseDistortionModel(const std::string& name, const std::string& source);

/// One camera stream: pinhole intrinsics plus its lens model.
struct StreamCalibration {
  CameraIntrinsics intrinsics;
  DistortionModel model = DistortionModel::kNone;
  std::array<double, 5> coeffs{};  ///< k1 k2 p1 p2 k3

  bool distorted() const;
  /// Pixel of a point in the stream's camera frame (z > 0).
  Eigen::Vector2d Project(const Eigen::Vector3d& p) const;
  /// The point at depth z (m) seen at pixel (u, v).
  Eigen::Vector3d Deproject(double u, double v, double z) const;
};

/// Reprojects a depth image of the depth camera into the colour camera: each
/// depth pixel becomes a 3-D point in the depth frame, moves to the colour
/// frame by colorMdepth (p_color = colorMdepth * p_depth), and fills the colour
/// pixels whose centres its footprint (the pixel's square, projected at its
/// depth, lens model included) covers; pixels no footprint covers that way take
/// the nearest of the footprints rounded out to whole pixels (cracks between
/// neighbours at slightly different depths). Where several points land, the
/// nearest wins; pixels no point reaches stay 0. Depth stays in the same units
/// (z along the colour axis). The depth camera's resolution bounds the result:
/// on a slanted surface a colour pixel may be off by the depth change across
/// one depth pixel.
/// @throws HardwareError when the image size disagrees with depth.intrinsics.
DepthImage AlignDepthToColor(const DepthImage& depth, const StreamCalibration& depth_stream,
                             const StreamCalibration& color_stream,
                             const Eigen::Isometry3d& colorMdepth, double depth_scale_m);

/// AlignDepthToColor for a stream of images from the same cameras: the rays of
/// the depth camera's pixels are computed once.
class DepthAligner {
 public:
  DepthAligner(const StreamCalibration& depth_stream, const StreamCalibration& color_stream,
               const Eigen::Isometry3d& colorMdepth, double depth_scale_m);
  /// @throws HardwareError when the image size disagrees with the depth intrinsics.
  DepthImage Align(const DepthImage& depth) const;

 private:
  StreamCalibration depth_, color_;
  Eigen::Vector3d t_;
  double depth_scale_m_;
  std::vector<Eigen::Vector3d> corner_rays_, centre_rays_;  // in the colour frame's orientation
};

/// For each colour stamp, the index of the depth stamp nearest in time, or -1
/// when it is further than `max_gap_s`. Both lists in seconds on the same clock,
/// each in increasing order.
std::vector<int> PairByStamp(const std::vector<double>& color_stamps_s,
                             const std::vector<double>& depth_stamps_s, double max_gap_s);

/// A stream's frame period: the median interval between its stamps (s);
/// infinite with fewer than two stamps. The pairing gap when none is given is
/// one period of the depth stream.
double MedianInterval(const std::vector<double>& stamps_s);

}  // namespace aerograsp
