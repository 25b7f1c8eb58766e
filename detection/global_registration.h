// Global pose initialisation without a prior (first frame, after a loss).
// Two sources of candidates, each refined by ICP:
//  - features: FPFH on voxel-downsampled model and scene clouds, matched by
//    PCL's SampleConsensusPrerejective (RANSAC that pre-rejects samples whose
//    edge lengths disagree);
//  - when the object's centre is roughly known (the detector's box and the
//    depth inside it): a fixed set of orientations placed there, each given a
//    short ICP on a subsampled cloud, the best few refined fully. Small,
//    box-like objects give FPFH few distinctive points; this does not need them.
// The caller ranks the candidates by how well they explain the depth image.
// PCL stays in the .cpp.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "detection/icp.h"
#include "detection/model_cloud.h"
#include "detection/scene_cloud.h"

namespace aerograsp {

struct GlobalRegistrationOptions {
  double voxel_m = 0.01;            ///< downsampling of both clouds, m
  double feature_radius_m = 0.035;  ///< FPFH support radius, m
  int max_iterations = 4000;        ///< RANSAC iterations per attempt
  int attempts = 2;                 ///< independent RANSAC runs (seeds seed, seed+1, ...)
  int orientations = 64;            ///< orientation hypotheses around a known centre (0: off)
  int refined_orientations = 3;     ///< the best of them refined with the full ICP
  double inlier_fraction = 0.3;     ///< of the scene points, for a RANSAC hypothesis to count
  std::uint64_t seed = 1;
};

/// The model's features, computed once per object.
class GlobalRegistration {
 public:
  GlobalRegistration(const ModelCloud& model, const GlobalRegistrationOptions& options = {});
  ~GlobalRegistration();
  GlobalRegistration(const GlobalRegistration&) = delete;
  GlobalRegistration& operator=(const GlobalRegistration&) = delete;

  /// Candidates for cMo from the scene (frame c), each refined with ICP, best
  /// first by ICP inliers (the caller ranks by depth support). `centres_c` are
  /// rough positions of the object's centre (m, in c): one from a detector box,
  /// or many spread over the frame when there is no detector (each then gets a
  /// quarter of the orientations). Empty when the scene has too few points or
  /// nothing converged. Never throws.
  std::vector<IcpResult> Candidates(const SceneCloud& scene, const IcpOptions& icp,
                                    const std::vector<Eigen::Vector3d>& centres_c = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aerograsp
