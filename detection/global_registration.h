// Global pose initialisation without a prior (first frame, after a loss).
// Two sources of candidates:
//  - hypotheses around a rough centre of the object (the detector's box and
//    the depth inside it, the last known pose, or a grid over the frame): a
//    fixed set of orientations placed there, each given a short ICP on the
//    scene points within the object's reach of that centre; the best few
//    (ranked by ICP inliers) are the candidates. Small, box-like objects give
//    FPFH few distinctive points; this does not need them;
//  - features: FPFH on voxel-downsampled model and scene clouds, matched by
//    PCL's SampleConsensusPrerejective (RANSAC that pre-rejects samples whose
//    edge lengths disagree). Its cost has no useful bound: it runs only when
//    the search's work per frame is not bounded.
// The hypotheses can be spread over frames: the caller gives each call a
// WorkBudget and the index of the next hypothesis, and counts the work in
// pairings (IcpWorkBound's unit). The caller refines the candidates and ranks
// them by how well they explain the depth image. PCL stays in the .cpp.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
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
  /// Independent RANSAC runs (seeds seed, seed+1, ...), >= 0; must be 0 when
  /// work_per_frame bounds the search.
  int attempts = 0;
  /// Feature matching (attempts > 0) also on a whole-frame search (no
  /// detector's box: the cloud is the whole frame, whole_frame_points); false:
  /// only on a detector's crop, a whole-frame search is its hypotheses alone.
  bool whole_frame_features = true;
  int orientations = 64;         ///< orientation hypotheses around a known centre (0: off)
  int refined_orientations = 3;  ///< the best of them refined with the full ICP
  double inlier_fraction = 0.3;  ///< of the scene points, for a RANSAC hypothesis to count
  std::uint64_t seed = 1;
  /// Work the search may do in one frame, in pairings (one scene point paired
  /// in one ICP pass, or one model point projected to score a pose), [0, 1e9];
  /// 0: no bound (the whole search in the frame that starts it). A search that
  /// does not fit continues on the next frames.
  std::int64_t work_per_frame = 1200000;
};

/// The work one frame may still do (pairings; limit 0: no bound), and what it did.
class WorkBudget {
 public:
  explicit WorkBudget(std::int64_t limit) : limit_(limit) {}
  /// Takes `units` when they fit (always, without a bound); false leaves the budget as it was.
  bool Take(std::int64_t units) {
    if (limit_ > 0 && used_ + units > limit_) return false;
    used_ += units;
    return true;
  }
  bool bounded() const { return limit_ > 0; }
  /// What is left of a bounded budget (0 without a bound).
  std::int64_t left() const { return limit_ > 0 ? limit_ - used_ : 0; }
  std::int64_t used() const { return used_; }

 private:
  std::int64_t limit_ = 0;
  std::int64_t used_ = 0;
};

/// The model's features and orientation hypotheses, computed once per object.
class GlobalRegistration {
 public:
  GlobalRegistration(const ModelCloud& model, const GlobalRegistrationOptions& options = {});
  ~GlobalRegistration();
  GlobalRegistration(const GlobalRegistration&) = delete;
  GlobalRegistration& operator=(const GlobalRegistration&) = delete;

  /// The number of hypotheses Hypotheses runs through for `centres` rough
  /// centres: every orientation for one centre, a quarter of them for each of
  /// several (every orientation for each with `every_orientation`: centres
  /// that are pieces of the scene the object's size, SegmentScene); 0 when
  /// the scene has too few points (under 30).
  std::size_t HypothesisCount(const SceneCloud& scene, std::size_t centres,
                              bool every_orientation = false) const;

  /// Runs hypotheses first, first + 1, ... (hypothesis h: centre h /
  /// per-centre count, orientation h % per-centre count; the object's box
  /// centre placed on the centre) as long as `budget` pays for them, on all
  /// cores; returns their short ICPs in that order (failed ones included): the
  /// caller continues from first + size() on a later frame. `centres_c` are
  /// rough positions of the object's centre (m, in c), the likeliest first.
  /// Each hypothesis also reserves `extra_work` pairings of the budget (the
  /// caller's scoring of it). Never throws.
  std::vector<IcpResult> Hypotheses(const SceneCloud& scene, const IcpOptions& icp,
                                    const std::vector<Eigen::Vector3d>& centres_c,
                                    std::size_t first, WorkBudget* budget,
                                    std::int64_t extra_work = 0,
                                    bool every_orientation = false) const;

  /// The best `refined_orientations` of the given hypotheses, failed ones left
  /// out: the highest `scores` first when given (one per hypothesis), else the
  /// most ICP inliers first (comparable only around one centre: elsewhere a
  /// centre on a large surface has more points to pair).
  std::vector<IcpResult> Best(std::vector<IcpResult> hypotheses,
                              const std::vector<double>& scores = {}) const;

  /// Candidates for cMo from FPFH feature matching (each refined with ICP).
  /// Empty with attempts 0, too few scene points or nothing converged. Never throws.
  std::vector<IcpResult> FeatureCandidates(const SceneCloud& scene, const IcpOptions& icp) const;

  /// The options of the short ICP given to each hypothesis.
  static IcpOptions QuickIcp(const IcpOptions& icp);

  /// The points of `scene` within `reach_m` of `centre_c` (every `stride`-th).
  static SceneCloud Near(const SceneCloud& scene, const Eigen::Vector3d& centre_c, double reach_m,
                         std::size_t stride = 1);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aerograsp
