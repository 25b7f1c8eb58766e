// Pinhole intrinsics of a camera stream (no distortion: the D435 colour stream
// is rectified), in pixels. Loaded from and saved to ViSP's camera XML.
#pragma once

#include <Eigen/Core>
#include <string>

namespace aerograsp {

struct CameraIntrinsics {
  int width = 640;    ///< pixels
  int height = 480;   ///< pixels
  double fx = 615.0;  ///< focal length along u, pixels
  double fy = 615.0;  ///< focal length along v, pixels
  double cx = 320.0;  ///< principal point u, pixels
  double cy = 240.0;  ///< principal point v, pixels

  /// Pixel (u, v) of a point in the camera frame (z > 0 is a precondition).
  Eigen::Vector2d Project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  /// The same camera at `scale` times the resolution (pixel centres kept:
  /// c' = (c + 0.5) * scale - 0.5), e.g. 0.5 for 640x480 -> 320x240.
  CameraIntrinsics Scaled(double scale) const {
    CameraIntrinsics k = *this;
    k.width = static_cast<int>(width * scale + 0.5);
    k.height = static_cast<int>(height * scale + 0.5);
    k.fx = fx * scale;
    k.fy = fy * scale;
    k.cx = (cx + 0.5) * scale - 0.5;
    k.cy = (cy + 0.5) * scale - 0.5;
    return k;
  }
  /// The point at depth z (m) seen at pixel (u, v), in the camera frame.
  Eigen::Vector3d Unproject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
  /// Horizontal and vertical field of view, degrees.
  double HorizontalFovDeg() const;
  double VerticalFovDeg() const;

  /// `prefix` is the key path of these values in `source`, ending in "." (""
  /// at the top); the keys are the fields' names (width, fx, cx, ...).
  /// @throws ConfigError "<source>: <prefix><field>: ..." for a non-positive
  /// size or focal length, or a principal point outside the image.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// Reads the camera named `camera_name` (any camera when empty) from a ViSP
/// camera XML file, model perspectiveProjWithoutDistortion.
/// @throws ConfigError naming the file when it is missing, unreadable, holds no
/// such camera, or its values fail Validate().
CameraIntrinsics LoadCameraXml(const std::string& path, const std::string& camera_name = "");

/// Writes the intrinsics as a ViSP camera XML under `camera_name`.
/// @throws ConfigError naming the file when it cannot be written.
void SaveCameraXml(const CameraIntrinsics& K, const std::string& camera_name,
                   const std::string& path);

}  // namespace aerograsp
