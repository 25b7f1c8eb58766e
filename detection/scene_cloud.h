// The local cloud of one RGB-D frame: the pixels inside a box (the detector's
// crop), unprojected with the colour intrinsics, subsampled on a pixel grid to
// a target size, each point with its colour and a normal fitted to its
// neighbourhood in the depth image.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/camera_model.h"
#include "core/image.h"

namespace aerograsp {

/// A pixel rectangle [x0, x1) x [y0, y1) of the 640x480 image.
struct PixelBox {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  /// Clipped to a w x h image.
  PixelBox Clipped(int w, int h) const;
  /// Grown by `fraction` of its size on every side.
  PixelBox Grown(double fraction) const;
};
/// Intersection over union of two boxes (0 when either is empty).
double BoxIoU(const PixelBox& a, const PixelBox& b);

struct SceneCloud {
  std::vector<Eigen::Vector3f> points_c;  ///< m, camera frame c
  /// unit, towards the camera; zero when it could not be fitted
  std::vector<Eigen::Vector3f> normals_c;
  std::vector<Eigen::Vector3f> colors;  ///< RGB 0..255
  int valid_pixels = 0;                 ///< pixels of the box with depth in range
  bool empty() const { return points_c.empty(); }
};

struct SceneCloudOptions {
  int target_points = 1000;   ///< subsample to about this many points, [50, 100000]
  double min_depth_m = 0.15;  ///< ignore nearer depth, m
  double max_depth_m = 3.0;   ///< ignore farther depth, m
  /// neighbourhood of the normal fit, m (its pixel radius is capped at 12)
  double normal_radius_m = 0.03;
  /// neighbours farther in depth than this are another surface, m
  double max_normal_jump_m = 0.03;
};

/// Builds the cloud of the pixels of `box` (clipped to the image). Depth and
/// colour must be the same size and aligned (RgbdFrame's contract); pixels with
/// depth 0 or outside [min_depth_m, max_depth_m] are skipped. An empty box, an
/// all-zero depth or a mismatch in sizes gives an empty cloud, never a throw.
SceneCloud BuildSceneCloud(const ColorImage& color, const DepthImage& depth, double depth_scale_m,
                           const CameraIntrinsics& K, const PixelBox& box,
                           const SceneCloudOptions& options = {});

}  // namespace aerograsp
