// The robot's own arms in the depth image. With the arms' measured joint
// positions at a frame's time and the camera's place on the body (dMc), the
// arms' collision shapes (the URDF boxes, cylinders and spheres of every
// segment, the gripper and its fingers included) are placed in the camera
// frame, and every depth pixel whose point lies inside a shape or within a
// margin of it is dropped (set to 0, "no data"). The tracker then neither
// pairs the fingers with the object (ICP) nor counts a part of the object the
// fingers hide as seen: a dropped pixel is no measurement, so the model points
// behind it are hidden, not contradicted (detection/pose_support.h).
//
// Only the pixels inside each shape's projected bounding box (grown by the
// margin) are tested. Mesh shapes are skipped, as in core/collision.h: the
// shipped arms describe every part with primitives. The fingers are where the
// URDF places them, fully open (as the simulator renders them); a real
// gripper's fingers close inwards by up to half its aperture.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "core/arm_model.h"
#include "core/camera_model.h"
#include "core/image.h"
#include "core/platform.h"

namespace aerograsp {

struct SelfFilterOptions {
  /// Drop the arms' pixels when the tracker is given the arms' joints.
  bool enabled = true;
  /// true: the arms' pixels leave the depth every stage sees (the cloud, ICP,
  /// the slide, the support check). false: they stay in the depth, and only
  /// the support check takes the model behind them as hidden rather than
  /// occluded: the fingers over the object no longer lower its coverage, and
  /// ICP and the slide still see what they saw without the filter.
  bool drop_from_depth = true;
  /// With drop_from_depth false: the arms' pixels still leave the cloud ICP
  /// pairs (a finger's surface cannot pull the pose), while the slide and the
  /// support check see the depth as the camera gave it, the model behind an
  /// arm pixel hidden. Without effect when drop_from_depth is true.
  bool drop_from_cloud = false;
  /// With drop_from_depth false: the support check takes the model behind the
  /// arms' pixels as hidden. Without effect when drop_from_depth is true.
  bool in_support = true;
  /// With drop_from_depth false: the slide along a weak direction does not
  /// take the outline where the object meets the arms' pixels for its end
  /// (SlideToBestSupport's arms_dropped). Without effect when drop_from_depth
  /// is true (the arms' pixels are then no data for the slide as well).
  bool in_slide = false;
  /// A depth point this near an arm's collision shape (or inside it) is the
  /// arm's, m, [0, 0.1]: the depth noise, the joints' and the calibration's
  /// error at the grasping range.
  double margin_m = 0.01;
  /// @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// Both arms' joint positions (rad), indexed as kSides (0 left, 1 right).
using ArmJointPositions = std::array<Eigen::VectorXd, 2>;

/// What one frame's filter did.
struct SelfFilterResult {
  int shapes = 0;          ///< shapes in front of the camera
  int tested_pixels = 0;   ///< pixel tests (a pixel in several shapes' boxes counts for each)
  int dropped_pixels = 0;  ///< pixels set to no data
};

class RobotSelfFilter {
 public:
  /// Copies the arms' models and bases (dMb) from `platform`.
  /// @throws ConfigError for options out of range (source "self_filter").
  RobotSelfFilter(const Platform& platform, const SelfFilterOptions& options);

  /// Drops the arms' pixels from `depth` (depth_scale_m m per unit, intrinsics K)
  /// for the joints q (an arm whose vector has the wrong size or a non-finite
  /// entry is left out) and the camera at dMc on the body. A depth image of
  /// another size than K, or a bad scale, is left as it is.
  SelfFilterResult Apply(const ArmJointPositions& q_rad, const Eigen::Isometry3d& dMc,
                         const CameraIntrinsics& K, double depth_scale_m, DepthImage* depth) const;

  const SelfFilterOptions& options() const { return options_; }

 private:
  struct Shape {
    int side = 0;
    int segment = 0;
    CollisionShape shape;
  };
  ArmModel arms_[2];
  Eigen::Isometry3d dMb_[2];
  SelfFilterOptions options_;
  std::vector<Shape> shapes_;
};

/// The arms' measured joints over the last moments, read at a frame's stamp:
/// a camera frame is taken before it is processed, and the arms move meanwhile.
class ArmJointHistory {
 public:
  /// Keeps the samples of the last `keep_s` seconds (> 0).
  explicit ArmJointHistory(double keep_s = 1.0) : keep_s_(keep_s) {}
  /// A sample at t_s (not older than the last one; an older one is ignored).
  void Add(double t_s, const ArmJointPositions& q_rad);
  /// The joints at t_s, linear between the two samples around it; the oldest or
  /// newest sample outside their span. Empty without samples.
  std::optional<ArmJointPositions> At(double t_s) const;

 private:
  double keep_s_;
  std::deque<std::pair<double, ArmJointPositions>> samples_;
};

}  // namespace aerograsp
