// How well a pose explains the depth image: the model's points that face the
// camera are projected at cMo and compared with the measured depth. A point
// agrees when the depth matches; it contradicts the pose when the camera sees
// through it (measured depth well behind it: free space where the model says
// there is surface); a nearer measurement is an occlusion and counts for
// nothing, and where that nearer surface is the model's own at the pose (the
// far inner wall of a pipe behind its near wall) the point is not visible at
// all: it leaves `projected`, so coverage() is of the model the camera can
// see. Where the depth agrees the colour must agree too (ColorDistance,
// the ICP's Eq. 3), else the point contradicts the pose: a plain wall at the
// right depth does not pass for the object. A model without colours (a plain
// mesh) is scored on depth alone. A wrong pose contradicts; a right pose
// behind an occluder does not. Where the occluder is the robot's own arm (a
// pixel the self filter takes for the arms, detection/self_filter.h), the
// model point behind it is hidden: the fingers over the object are no
// missing evidence of it.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>

#include "core/camera_model.h"
#include "core/image.h"
#include "detection/model_cloud.h"
#include "detection/scene_cloud.h"

namespace aerograsp {

struct PoseSupport {
  /// Front-facing model points inside the image with measured depth, less
  /// those the model itself hides there.
  int projected = 0;
  int agree = 0;
  int see_through = 0;  ///< the camera sees through the model, or the colour disagrees
  int occluded = 0;
  /// Model points behind the robot's arm's pixels (hidden: not in projected).
  int behind_arm = 0;
  /// agree / (agree + see_through); 0 when nothing was compared.
  double ratio() const {
    return agree + see_through > 0 ? double(agree) / (agree + see_through) : 0.0;
  }
  /// agree / projected: how much of the visible model is explained.
  double coverage() const { return projected > 0 ? double(agree) / projected : 0.0; }
  PixelBox box;  ///< bounding box of the projected front-facing points
  /// Bounding box of the agreeing points: where the pose explains the image
  /// (the part of the object the fingers leave in view, for a true pose).
  PixelBox agree_box;
};

struct PoseSupportOptions {
  int max_points = 400;                ///< model points tested (strided over the model)
  double depth_noise_per_m2 = 0.0047;  ///< depth tolerance max(min_tolerance_m, 3 * this * z^2)
  double min_tolerance_m = 0.01;
  double max_color_distance = 100.0;  ///< colour check (ColorDistance); >= 768 disables it
};

/// `color` may be empty (no colour check). `arms_dropped`, when given, is
/// `depth` with the robot's own pixels set to no data (RobotSelfFilter::Apply
/// on a copy): a model point seen behind such a pixel (nearer, or at its depth
/// in another colour) is hidden, not occluded; ignored unless its size is
/// `depth`'s. Never throws; bad input gives an empty support.
PoseSupport ScorePoseSupport(const ModelCloud& model, const Eigen::Isometry3d& cMo,
                             const ColorImage& color, const DepthImage& depth, double depth_scale_m,
                             const CameraIntrinsics& K, const PoseSupportOptions& options = {},
                             const DepthImage* arms_dropped = nullptr);

/// The most model points ScorePoseSupport projects (the global registration's
/// work unit, IcpWorkBound's pairings, counts them alike).
std::size_t SupportWorkBound(const ModelCloud& model, const PoseSupportOptions& options = {});

/// The best slide and how sharply the support locates it.
struct SlideFit {
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  /// The smaller loss of score (agreeing minus contradicting points) probe_m to
  /// either side of the best offset: about 0 when nothing visible ends the
  /// object along the direction (both ends hidden), so the slide is a guess.
  int drop = 0;
};

/// Slides cMo along `direction_o` (unit, frame o) by up to +-range_m (coarse
/// steps of 4 * step_m, then step_m around the best) and returns the offset
/// whose pose the depth and colour support best (agreeing minus contradicting
/// points): the outline fixes what ICP's point-to-plane pairs cannot when the
/// object could slide along a face. `arms_dropped` (as for ScorePoseSupport):
/// the drop counts the model points a probe moves behind the arms' pixels as
/// agreeing, so an end that stops where a finger hides the object is no end.
SlideFit SlideToBestSupport(const ModelCloud& model, const Eigen::Isometry3d& cMo,
                            const Eigen::Vector3d& direction_o, const ColorImage& color,
                            const DepthImage& depth, double depth_scale_m,
                            const CameraIntrinsics& K, const PoseSupportOptions& options = {},
                            double range_m = 0.04, double step_m = 0.001, double probe_m = 0.01,
                            const DepthImage* arms_dropped = nullptr);

/// The most model-point projections SlideToBestSupport makes with these arguments.
std::size_t SlideWorkBound(const ModelCloud& model, const PoseSupportOptions& options = {},
                           double range_m = 0.04, double step_m = 0.001);

}  // namespace aerograsp
