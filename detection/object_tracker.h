// The perception pipeline of one object (docs/design.md, Modules): detector box ->
// crop -> local cloud -> (global init when there is no prior) -> ICP seeded by
// the EKF prediction -> depth support check -> EKF update with gating ->
// confidence and found / lost. One call per frame; no threads, no files (the
// detector's model is loaded by the caller).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/object_model.h"
#include "detection/box_detector.h"
#include "detection/global_registration.h"
#include "detection/icp.h"
#include "detection/model_cloud.h"
#include "detection/pose_ekf.h"
#include "detection/pose_support.h"
#include "detection/scene_cloud.h"
#include "detection/scene_segmentation.h"
#include "detection/self_filter.h"
#include "detection/track_monitor.h"

namespace aerograsp {

struct PerceptionOptions {
  ModelCloudOptions model;
  SceneCloudOptions cloud;
  IcpOptions icp;
  GlobalRegistrationOptions global;
  /// Where the whole-frame search (no detector) looks: pieces of the scene
  /// off its large surfaces (detection/scene_segmentation.h).
  SegmentationOptions segment;
  PoseEkfOptions ekf;
  TrackMonitorOptions track;
  /// The arms' own pixels dropped from the depth before the cloud, ICP and the
  /// support check, when Process is given the arms' joints (SetRobot).
  SelfFilterOptions self_filter;
  float min_detection_score = 0.3f;  ///< detector peaks below this are ignored, (0, 1)
  double box_margin = 0.15;          ///< the crop is the box grown by this fraction per side
  /// The detector's box gives the search two centres: behind the median depth
  /// inside it and behind this quantile of it (the object's near surface), [0, 0.5];
  /// 0.5 (the median itself) gives the box one centre (see TwoCentresInBox).
  double near_centre_quantile = 0.1;
  /// a pose must explain this fraction of the compared depth, (0, 1]
  double min_support_ratio = 0.9;
  double min_coverage = 0.4;  ///< ... and this fraction of the visible model, (0, 1]
  /// On a frame with a detector's box, a pose passes only when at least this
  /// fraction of the outline of what it explains (PoseSupport::agree_box)
  /// lies inside the crop (the box grown by box_margin), [0, 1]; 0: no check.
  /// A pose fitted on the crop's edge (a look-alike surface around the
  /// object: the support pipe under a pipe, slid along it) is not the
  /// detected object; a true pose whose ends the fingers hide explains only
  /// the part the detector saw. When the track's own pose is refused so, the
  /// track is forgotten (filter and last good pose) and the box searched: the
  /// frames without a box do not find the look-alike again from where it was.
  double min_box_overlap = 0.0;
  /// On a frame with a detector's box, a pose passes only when the outline of
  /// what it explains (PoseSupport::agree_box) also covers at least this
  /// fraction of the box's area, [0, 1]; 0: no check. The box is the object
  /// the detector saw: a look-alike in its crop (the support pipe under the
  /// pipe, slid along it, or seen farther along the rays) explains another or
  /// a smaller part of the image. A track's own pose refused so is forgotten
  /// as with min_box_overlap.
  double min_box_cover = 0.0;
  int min_cloud_points = 60;  ///< fewer points in the crop: no measurement, >= 10
  /// cloud size when the crop is the whole frame (no detector, no prior), [50, 100000]
  int whole_frame_points = 8000;
  /// While the track is found and the last frame was measured, the detector
  /// runs on every this many frames, [1, 30]; on the frames between, the crop
  /// is the outline of the filter's prediction. 1: every frame (the paper's
  /// pipeline). The CNN is a quarter of a tracked frame's time.
  int detect_every_frames = 1;
  /// After this many consecutive frames on which the detector ran and found no
  /// box (a detector that does not see the object: a board on it, other light),
  /// the crop is the whole frame and the search the segmented one of a tracker
  /// without a detector, until the detector finds a box again; frames, [0, 1000],
  /// 0: never (only the detector's box is searched).
  int frames_without_box_to_search_frame = 30;
  /// After a global registration that tried everything in vain, the next one
  /// starts this many frames later, [1, 30]; 1: on every frame that needs one.
  /// While the object is lost the search is most of a frame's CPU; the frames
  /// between still try ICP from the last pose, so a track that shows again
  /// where it was lost continues at once.
  int lost_search_every_frames = 1;
  /// The global registration (~0.1 s of CPU a frame) runs only for an object
  /// centre (from the depth in its box) this far from the camera, m: beyond
  /// the 1.5 m it is validated at it fails anyway, and nearer than the
  /// vehicle's own parts reach (on the mission's approach the detector's
  /// weakest boxes fell on the arms at 0.27 m: 60 frames). 0 <= min < max <= 10.
  double min_global_range_m = 0.35;
  double max_global_range_m = 1.6;
  /// A found track, once lost, is re-found by the global registration only
  /// within this distance of its last measured pose, m, (0, 10]; the distance
  /// grows at reacquire_speed_mps (m/s, [0, 10]) from the time of that pose.
  /// An object does not jump: a look-alike elsewhere in the frame (the support
  /// pipe under a hidden pipe, 0.8 m away) must not take the track. Sized for
  /// a crawling object seen from a swaying vehicle.
  double reacquire_radius_m = 0.15;
  double reacquire_speed_mps = 0.2;
  double measurement_position_std_m = 0.002;   ///< ICP position noise at 1 m (grows with z^2), m
  double measurement_rotation_std_rad = 0.02;  ///< ICP rotation noise, rad
  int gated_frames_to_reset = 3;  ///< consecutive gated but well-supported poses restart the filter
  /// ICP's weak_ratio below this: slide along it to the best outline, [0, 1]
  double weak_direction_ratio = 0.08;
  /// Position noise added along ICP's weak direction when weak_ratio is below
  /// weak_direction_ratio (an extrusion seen without its ends), m, [0, 1]. Worth
  /// setting only with the camera's pose given to Process (a filter in the
  /// world, where the object moves slowly); 0 leaves the noise isotropic.
  double weak_direction_std_m = 0.0;
  /// A slide along the weak direction whose outline support drops by at least
  /// this many points a probe away fixes the pose along it
  /// (ObjectEstimate::weak_direction_fixed), [0, 100000] points.
  int weak_direction_min_drop = 50;
  /// Checks every field, the stages' options included (the bounds in their
  /// comments; detection/perception_config.h reads them from a file).
  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// Whether the search places its orientations on two centres in a detector's box
/// (the median depth and `near_centre_quantile`) rather than one.
inline bool TwoCentresInBox(const PerceptionOptions& options) {
  return options.near_centre_quantile < 0.5;
}

/// Whether a pose whose outline is `outline` (PoseSupport::agree_box) lies
/// in a detector's crop: at least `min_fraction` of the outline's area inside
/// `crop`. Always with min_fraction 0; never for an empty outline otherwise.
bool OutlineInCrop(const PixelBox& outline, const PixelBox& crop, double min_fraction);

/// Whether the outline of what a pose explains (PoseSupport::agree_box) covers
/// a detector's `box`: at least `min_fraction` of the box's area inside
/// `outline`. Always with min_fraction 0; never for an empty outline otherwise.
bool OutlineCoversBox(const PixelBox& outline, const PixelBox& box, double min_fraction);

/// What the pipeline knows about the object after a frame.
struct ObjectEstimate {
  double stamp_s = 0.0;
  bool valid = false;  ///< a pose exists (the filter has been initialised at some time)
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  /// The pose in the frame the filter runs in (f): the world when Process was
  /// given the camera's pose wMc, else the camera (then fMo = cMo).
  Eigen::Isometry3d fMo = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_f = Eigen::Vector3d::Zero();  ///< m/s, in f
  /// position m^2, rotation rad^2, in f
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Vector3d v_c = Eigen::Vector3d::Zero();  ///< m/s in f, expressed in c
  Eigen::Vector3d w_c = Eigen::Vector3d::Zero();  ///< rad/s in f, expressed in c
  double confidence = 0.0;                        ///< [0, 1]
  TrackState state = TrackState::kLost;
  /// This frame measured the pose along every direction: ICP left no weak
  /// direction, or the outline fixed the slide along it (at least
  /// weak_direction_min_drop points). False when not measured, or along an
  /// extrusion seen without its ends.
  bool weak_direction_fixed = false;
};

/// Milliseconds of CPU time per stage of one frame (detect_ms 0 on a frame the
/// detector skipped, PerceptionOptions::detect_every_frames): the calling
/// thread's, except global_ms, the whole process's during the global
/// registration (it runs on all cores).
struct StageTimes {
  double self_filter_ms = 0, detect_ms = 0, cloud_ms = 0, global_ms = 0, icp_ms = 0, filter_ms = 0,
         total_ms = 0;
};

/// Everything about one frame, for reports and tests.
struct FrameReport {
  ObjectEstimate estimate;
  std::optional<Detection> detection;  ///< the best box, when the detector found one
  PixelBox crop;                       ///< the crop used (empty: no measurement attempted)
  /// The robot's own pixels dropped (SetRobot and joints given), else all 0.
  SelfFilterResult self_filter;
  int cloud_points = 0;
  bool measured = false;     ///< a pose passed ICP and the support check
  bool global_init = false;  ///< global registration ran this frame
  /// Its work this frame, in pairings (GlobalRegistrationOptions::work_per_frame's unit).
  std::int64_t global_work = 0;
  bool gated = false;  ///< the measurement was rejected by the EKF gate
  /// The track's own pose explained the depth outside the detector's crop
  /// (PerceptionOptions::min_box_overlap): the track was forgotten this frame.
  bool forgot_track = false;
  IcpResult icp;
  PoseSupport support;
  /// SlideFit::drop of the measured pose's slide along ICP's weak direction;
  /// -1: ICP left no weak direction.
  int outline_drop = -1;
  double nis = 0.0;
  StageTimes times;
};

/// How the global registration fared over the frames processed so far. A
/// search starts on a frame that needs one and ends when it finds the object
/// or has tried every hypothesis and candidate (spread over frames when
/// GlobalRegistrationOptions::work_per_frame bounds each frame's share).
struct GlobalSearchStats {
  int frames = 0;         ///< frames the search ran in
  int searches = 0;       ///< searches started
  int found = 0;          ///< searches that found the object
  int exhausted = 0;      ///< searches that tried everything in vain
  std::int64_t work = 0;  ///< pairings, all frames
  double cpu_ms = 0.0;    ///< CPU time of all threads, all frames
  int max_frames = 0;     ///< the most frames one search took (ended ones)
};

/// The model cloud a tracker of `object` builds with these options (its
/// symmetries the object's): built once, it can be given to every tracker of
/// the same object and options (the seeded missions of one configuration).
/// @throws std::invalid_argument as BuildModelCloud.
std::shared_ptr<const ModelCloud> BuildTrackerModel(const ObjectModel& object,
                                                    const ModelCloudOptions& options);

class ObjectTracker {
 public:
  /// `detector` may be null: then every crop is the whole frame (global
  /// registration on the whole frame when there is no prior).
  /// @throws ConfigError naming the option and its bound for options out of range.
  ObjectTracker(const ObjectModel& object, const PerceptionOptions& options,
                std::unique_ptr<BoxDetector> detector);
  /// The same with the model cloud built already (BuildTrackerModel of this
  /// object and options.model; null: built here), shared with other trackers.
  ObjectTracker(const ObjectModel& object, const PerceptionOptions& options,
                std::unique_ptr<BoxDetector> detector, std::shared_ptr<const ModelCloud> model);
  ~ObjectTracker();
  ObjectTracker(const ObjectTracker&) = delete;
  ObjectTracker& operator=(const ObjectTracker&) = delete;

  /// A known first pose (e.g. --init-pose): used as the prior of the next frame.
  void SetInitialPose(const Eigen::Isometry3d& cMo);

  /// Something of unknown appearance covers the object inside the box bMo (b
  /// from o, half extents m along b's axes): a tag board or a label fixed on it.
  /// The mesh's colours there are not compared with the image (ForgetColorsInBox).
  void ForgetColorsInBox(const Eigen::Isometry3d& oMb, const Eigen::Vector3d& half_extents_m);

  /// The camera rides on `platform` (its arms, their bases and dMc, the
  /// camera-to-body calibration, are copied): frames given the arms' joints
  /// have the arms' pixels dropped (PerceptionOptions::self_filter; nothing
  /// when it is disabled).
  void SetRobot(const Platform& platform);

  /// Processes one aligned colour + depth frame. Bad data (empty or all-zero
  /// depth, wrong sizes, no object) yields a lost or unmeasured estimate; never throws.
  /// With the camera's pose wMc at the frame (the vehicle's odometry) the
  /// filter runs in the world, where a crawling object moves slowly, instead
  /// of in the camera, which sways with the vehicle. Give it for every frame
  /// of a track or for none. `arm_joints`: the arms' measured joints at the
  /// frame's stamp (ArmJointHistory), for the self filter (SetRobot).
  FrameReport Process(const ColorImage& color, const DepthImage& depth, double stamp_s,
                      const CameraIntrinsics& K, double depth_scale_m,
                      const std::optional<Eigen::Isometry3d>& wMc = std::nullopt,
                      const std::optional<ArmJointPositions>& arm_joints = std::nullopt);

  const ModelCloud& model() const { return *model_; }
  const PerceptionOptions& options() const { return options_; }
  const GlobalSearchStats& global_stats() const { return global_stats_; }
  bool has_detector() const { return detector_ != nullptr; }

 private:
  /// The best pose (ICP from `seed`, else global registration when allowed) for the crop.
  /// `own_track`: the seed is the track's own pose and the box check is on: a
  /// pose from it that explains the depth but lies outside the detector's crop
  /// forgets the track (ForgetTrack) and the box is searched.
  bool Measure(const SceneCloud& cloud, const ColorImage& color, const DepthImage& depth,
               double depth_scale_m, const CameraIntrinsics& K,
               const std::optional<Eigen::Isometry3d>& seed,
               const std::vector<Eigen::Vector3d>& centres_c, bool allow_global, bool segment,
               std::size_t kept_centres, bool own_track, FrameReport* report);
  /// A rough object centre (m, in c) from a detector box and the depth inside it
  /// (its median, or the given quantile).
  std::optional<Eigen::Vector3d> EstimateCentre(const PixelBox& box, const DepthImage& depth,
                                                double depth_scale_m, const CameraIntrinsics& K,
                                                double quantile = 0.5) const;

  /// This frame's share of the global registration (hypotheses, then their
  /// refinement, as far as the budget goes): true when it found a pose.
  /// `segment`: the cloud is the whole frame and no detector gives a box: the
  /// search starts by segmenting the scene (SegmentScene) and searches around
  /// its pieces, after the first `kept_centres` of `centres_c` (the last known
  /// place); the grid of `centres_c` only when no piece fits the object.
  bool Search(const SceneCloud& cloud, const ColorImage& color, const DepthImage& depth,
              double depth_scale_m, const CameraIntrinsics& K,
              const std::vector<Eigen::Vector3d>& centres_c, bool segment, std::size_t kept_centres,
              FrameReport* report);
  /// A centre within the global registration's range (min/max_global_range_m).
  bool InGlobalRange(const Eigen::Vector3d& c) const;
  /// ... and inside this frame's reacquisition zone (grown by the object's radius).
  bool Reachable(const Eigen::Vector3d& c) const;
  /// Drops the centres that are not Reachable.
  void KeepReachable(std::vector<Eigen::Vector3d>* centres_c) const;
  /// Ends the search under way: it found the object, tried everything, or is
  /// no longer needed (the track was measured without it, a pose was given).
  enum class SearchEnd { kFound, kExhausted, kAbandoned };
  void EndSearch(SearchEnd end);
  /// A pose explains enough of the depth (min_support_ratio, min_coverage)
  /// and, on a frame with a detector's box, lies in its crop (min_box_overlap)
  /// and covers the box (min_box_cover).
  bool Passes(const PoseSupport& support, const FrameReport& report) const;
  /// The pose explains enough of the depth (min_support_ratio, min_coverage).
  bool ExplainsDepth(const PoseSupport& support) const;
  /// The pose explains the depth but, on a frame with a detector's box, lies
  /// outside its crop (min_box_overlap) or does not cover the box
  /// (min_box_cover): a look-alike beside the object.
  bool OutsideBox(const PoseSupport& support, const FrameReport& report) const;
  /// Drops the filter, the track's state and its last good pose: nothing seeds
  /// the next frames from a pose found to lie on a look-alike.
  void ForgetTrack();
  /// The support of cMo in this frame (the arms' pixels hidden when they stay
  /// in the depth, SelfFilterOptions::drop_from_depth).
  PoseSupport Support(const Eigen::Isometry3d& cMo, const ColorImage& color,
                      const DepthImage& depth, double depth_scale_m,
                      const CameraIntrinsics& K) const;
  /// The rough centres of the object (m, in c) for the global registration, likeliest first.
  std::vector<Eigen::Vector3d> SearchCentres(const FrameReport& report, const DepthImage& depth,
                                             double depth_scale_m, const CameraIntrinsics& K,
                                             const std::optional<Eigen::Isometry3d>& prior) const;

  PoseSupportOptions SupportOptions() const;
  /// ICP from cMo, then, when the pairs leave a sliding direction, the slide the
  /// depth outline supports best (over the full range when the outline puts the
  /// object beyond slide_range_m) and ICP again. outline_drop: that slide's
  /// SlideFit::drop, -1 without a slide.
  IcpResult Register(const SceneCloud& cloud, const ColorImage& color, const DepthImage& depth,
                     double depth_scale_m, const CameraIntrinsics& K, const Eigen::Isometry3d& cMo,
                     double slide_range_m, int* outline_drop) const;

  PerceptionOptions options_;
  IcpOptions frame_icp_;  ///< options_.icp with the depth noise scaled to this frame's width
  std::shared_ptr<const ModelCloud> model_;  ///< never null; ForgetColorsInBox copies it
  std::unique_ptr<BoxDetector> detector_;
  std::unique_ptr<GlobalRegistration> global_;
  std::unique_ptr<RobotSelfFilter> self_filter_;  ///< SetRobot's, when enabled
  Eigen::Isometry3d robot_dMc_ = Eigen::Isometry3d::Identity();
  DepthImage filtered_depth_;  ///< this frame's depth without the arms
  /// This frame's arms stay in the depth and filtered_depth_ tells the
  /// support check where they are.
  bool arms_in_depth_ = false;
  /// The global registration's search under way, across frames.
  struct SearchState {
    bool active = false;
    int frames = 0;
    std::size_t next_hypothesis = 0;
    bool whole_frame = false;      ///< on the whole frame without a detector's box
    bool segment_pending = false;  ///< the scene is still to be segmented
    /// Segmented: the search runs on `foreground` around `centres_c` (from its first frame).
    bool segmented = false;
    SceneCloud foreground;
    std::vector<Eigen::Vector3d> centres_c;
    std::vector<IcpResult> hypotheses;  ///< the short ICPs so far
    std::vector<double> scores;         ///< their support scores, around several centres
    bool hypotheses_done = false;
    std::vector<IcpResult> candidates;  ///< the best hypotheses, once all have run
    std::size_t next_candidate = 0;
    std::int64_t saved_work = 0;  ///< budget carried over to pay for a step too big for one frame
  };
  SearchState search_;
  GlobalSearchStats global_stats_;
  PoseEkf ekf_;
  TrackMonitor monitor_;
  std::optional<Eigen::Isometry3d> last_good_fMo_;  // in the filter frame f
  double last_good_stamp_s_ = 0.0;
  /// This frame's limit on a re-found pose (centre m in c, radius m), if any.
  std::optional<std::pair<Eigen::Vector3d, double>> reacquire_zone_c_;
  bool was_found_ =
      false;  // the track has been found: a pose tracked on from its own last pose continues it
  std::optional<Eigen::Isometry3d> initial_cMo_;
  int gated_in_a_row_ = 0;
  int frames_since_detection_ = 0;  // frames processed since the detector last ran
  int frames_without_box_ = 0;      // consecutive frames the detector ran and found no box
  bool last_measured_ = false;      // the previous frame gave a measurement
  double min_half_extent_m_ = 0.05;
  /// Frames processed since a global registration last tried everything in
  /// vain, counted up to kNoFailedSearch (beyond any lost_search_every_frames).
  static constexpr int kNoFailedSearch = 1000;
  int frames_since_failed_search_ = kNoFailedSearch;
};

}  // namespace aerograsp
