// Point-to-plane ICP of a scene cloud (frame c) onto the model cloud (frame o)
// with the paper's three correspondence rejectors (Sect. 3, Eqs. 1-3): every
// candidate pair (scene point, nearest model point) must pass
//   Eq. 1  distance  |p - q| <= max_distance_m,
//   Eq. 2  normals   cos(angle(n_p, n_q)) >= min_normal_cos,
//   Eq. 3  colour    |R1-R2| + |G1-G2| + |B1-B2| <= max_color_distance
// Each rejector is applied unconditionally when its threshold is set and
// counts what it rejected, so a test can see that it ran; Eq. 3 needs a model
// with colours (ModelCloud::has_colors): a plain mesh's pairs pass it. Colours are compared
// after normalising their brightness (sum R+G+B scaled to 384), so shading by
// the light does not look like a different colour.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>

#include "detection/model_cloud.h"
#include "detection/scene_cloud.h"

namespace aerograsp {

/// RGB (0..255 each) scaled to a brightness of 384 (the channels' sum; a sum
/// below 1 counts as 1): what ColorDistance compares.
inline Eigen::Vector3f BrightnessNormalized(const Eigen::Vector3f& rgb) {
  return rgb * (384.0f / std::max(rgb.sum(), 1.0f));
}

/// Eq. 3 on brightness-normalised RGB (0..255 each): 0 for the same hue and
/// saturation, up to 768. The L1 distance of BrightnessNormalized(rgb_a) and
/// BrightnessNormalized(rgb_b), so a caller comparing many colours with one
/// may normalise that one once (the same float).
float ColorDistance(const Eigen::Vector3f& rgb_a, const Eigen::Vector3f& rgb_b);

struct RejectorThresholds {
  double max_distance_m = 0.02;  ///< Eq. 1, m, > 0
  /// The scene point's pixel ray (unit, the pair's frame), or zero. When set,
  /// Eq. 1 measures across the ray against max_distance_m and along it against
  /// max_along_ray_m: a depth camera's noise lies along its rays.
  Eigen::Vector3f ray = Eigen::Vector3f::Zero();
  double max_along_ray_m = 0.0;     ///< m, >= max_distance_m
  double min_normal_cos = 0.5;      ///< Eq. 2, [-1, 1]; -1 disables
  double max_color_distance = 100;  ///< Eq. 3, (0, 768]; >= 768 disables
};

enum class Rejection { kNone, kNoModelPoint, kDistance, kNormal, kColor };

/// Applies Eq. 1, then Eq. 2 (skipped for a zero scene normal), then Eq. 3 to
/// one pair; points, normals and the ray in the same frame.
Rejection ClassifyPair(const Eigen::Vector3f& p, const Eigen::Vector3f& n_p,
                       const Eigen::Vector3f& rgb_p, const Eigen::Vector3f& q,
                       const Eigen::Vector3f& n_q, const Eigen::Vector3f& rgb_q,
                       const RejectorThresholds& thresholds);

/// Where the depth noise's 3 sigma exceeds Eq. 1's final distance (beyond
/// about 0.75 m on a D435 with the defaults), each scene point is paired with
/// the model point where its pixel's ray meets the model's surface near it
/// (found from the nearest point by a few steps along the ray, at most 3
/// sigma), not with the nearest model point: noise moves a point along its
/// ray, so the nearest point sits off to the side of it at edges, and that
/// biased a noisy view's pose by degrees (4 deg of roll at 1.5 m on the
/// crawler). Nearer, pairs are nearest points, with Eq. 1 in 3D.
struct IcpOptions {
  int max_iterations = 12;         ///< [1, 100]
  double start_distance_m = 0.03;  ///< Eq. 1 threshold at the first iteration, m
  double end_distance_m = 0.008;   ///< ... shrinking geometrically to this at the last, m
  /// Depth noise std = this * z^2 (D435: s / (f b)) in a 640-pixel-wide depth
  /// image; floors Eq. 1 along the ray at 3 sigma. The tracker scales it by
  /// 640 / width for other widths (f halves at 320x240: the noise doubles).
  double depth_noise_per_m2 = 0.0047;
  double min_normal_cos = 0.5;  ///< Eq. 2
  /// Eq. 2 for a model without colours (ModelCloud::has_colors false), where
  /// Eq. 3 cannot reject the background's pairs: a stricter normal check
  /// does it instead, [-1, 1].
  double min_normal_cos_without_color = 0.8;
  double max_color_distance = 100.0;  ///< Eq. 3
  /// Weight of a point-to-point term beside point-to-plane: without it a box seen
  /// on two faces slides freely along their common edge. [0, 1]
  double point_to_point_weight = 0.1;
  /// Levenberg damping on the 6x6 normal equations (pins unobservable spins)
  double damping = 1e-4;
  /// stop when the step is below this (translation + rotation * 0.1 m)
  double converged_step_m = 2e-5;
  int min_inliers = 30;  ///< fewer pairs than this: failure
};

struct IcpResult {
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  bool ok = false;  ///< enough inliers and a finite pose
  int iterations = 0;
  int scene_points = 0;
  int inliers = 0;            ///< pairs that passed all rejectors at the last iteration
  double inlier_ratio = 0.0;  ///< inliers / scene points
  double rmse_m = 0.0;        ///< point-to-plane RMS of the inliers at the last iteration
  /// The translation the point-to-plane pairs constrain least (unit, frame o),
  /// and how weakly: smallest / largest eigenvalue of sum(n n^T) over the
  /// inliers. Near 0 when the object could slide (a box seen on two faces,
  /// a pipe along its axis); only the object's outline fixes it then.
  Eigen::Vector3d weak_direction_o = Eigen::Vector3d::UnitX();
  double weak_ratio = 1.0;
  /// Pairs rejected at the last iteration by each rejector.
  int rejected_no_model = 0, rejected_distance = 0, rejected_normal = 0, rejected_color = 0;
};

/// The most pairings (one scene point classified in one pass, the final pass
/// included) RefinePoseIcp makes on `scene_points` points: the unit in which
/// the global registration's work per frame is counted and bounded.
std::size_t IcpWorkBound(std::size_t scene_points, const IcpOptions& options);

/// Refines cMo starting from cMo_init. Never throws; `ok` is false when too few
/// pairs survive or the solution is not finite.
IcpResult RefinePoseIcp(const ModelCloud& model, const SceneCloud& scene,
                        const Eigen::Isometry3d& cMo_init, const IcpOptions& options = {});

}  // namespace aerograsp
