// Where an object of known size may be in a whole frame, without a detector:
// the large surfaces of the scene (planes and cylinders much longer than the
// object: a floor, a table, a wall, a support pipe) are found by RANSAC on the
// cloud's points and normals and set aside; what is left is split into
// connected pieces (neighbours on the pixel grid at a similar depth), and the
// pieces no larger than the object are the candidates, most points first.
// The global registration then searches around those pieces only, on the
// points off the large surfaces: a pose half buried in the support pipe or
// lying on the floor has nothing there to pair with.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "detection/scene_cloud.h"

namespace aerograsp {

struct SegmentationOptions {
  /// Large surfaces set aside before clustering, at most this many, [0, 10] (0: off).
  int max_surfaces = 4;
  /// RANSAC samples per surface searched (each tries a plane and a cylinder), [1, 10000].
  int surface_iterations = 100;
  /// A point within this distance of a surface (and with a normal within
  /// about 25 degrees of it) belongs to it, m, (0, 0.1].
  double surface_tolerance_m = 0.008;
  /// A surface whose points spread over more than this many times the
  /// object's diameter is background, [1, 100].
  double surface_extent = 1.5;
  /// Two neighbouring points are one piece when nearer than this, or than
  /// 2.5 pixel strides at their depth if that is more, m, (0, 0.5].
  double cluster_gap_m = 0.015;
  /// The most pieces given as candidates, [1, 100].
  int max_candidates = 8;
  std::uint64_t seed = 1;  ///< RANSAC's sampling seed
  /// @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

struct SceneSegments {
  /// The cloud's points off the large surfaces (the whole cloud when none was found).
  SceneCloud foreground;
  /// Rough centres (m, in c) of the pieces the object's size could be, most points first.
  std::vector<Eigen::Vector3d> centres_c;
  int surfaces = 0;  ///< large surfaces set aside
};

/// Segments `scene` (a whole-frame cloud, K its camera) for an object whose
/// largest extent is `object_diameter_m` and whose bounding sphere has radius
/// `object_radius_m`; `depth_behind_m` (the object's smallest half extent)
/// puts a piece's centre behind its visible surface; `depth_noise_per_m2`
/// (IcpOptions' depth noise) widens the surfaces' tolerance with depth. Never throws.
SceneSegments SegmentScene(const SceneCloud& scene, const CameraIntrinsics& K,
                           double object_diameter_m, double object_radius_m, double depth_behind_m,
                           double depth_noise_per_m2, const SegmentationOptions& options);

/// The most work SegmentScene does on `points` points, in pairings (one point
/// tested against one surface or neighbour: GlobalRegistrationOptions::work_per_frame's unit).
std::int64_t SegmentWorkBound(std::size_t points, const SegmentationOptions& options);

}  // namespace aerograsp
