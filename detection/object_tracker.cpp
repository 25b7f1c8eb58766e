#include "detection/object_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/config.h"
#include "core/parallel.h"
#include "core/thread_clock.h"
#include "detection/global_registration.h"

namespace aerograsp {
namespace {

/// The slide search's range without a close prediction (and when a short one
/// finds the object beyond itself).
constexpr double kFullSlideM = 0.04;

/// Throws ConfigError "<source>: <prefix><field>: <what>" unless `ok`.
struct FieldCheck {
  const std::string& source;
  const std::string& prefix;
  void operator()(bool ok, const char* field, const char* what) const {
    if (!ok) throw ConfigError(source + ": " + prefix + field + ": " + what);
  }
};

/// Pixels two boxes share (0 when they do not meet).
double SharedArea(const PixelBox& a, const PixelBox& b) {
  const PixelBox inside{std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1),
                        std::min(a.y1, b.y1)};
  return inside.empty() ? 0.0 : double(inside.width()) * inside.height();
}

/// Whether `outline` and `other` share at least min_fraction of the area of
/// `of` (one of the two): 0 is no check; an empty box shares nothing.
bool SharesAtLeast(const PixelBox& outline, const PixelBox& other, const PixelBox& of,
                   double min_fraction) {
  if (min_fraction <= 0.0) return true;
  if (outline.empty() || other.empty()) return false;
  const double shared = SharedArea(outline, other);
  return shared > 0.0 && shared >= min_fraction * double(of.width()) * of.height();
}

}  // namespace

bool OutlineInCrop(const PixelBox& outline, const PixelBox& crop, double min_fraction) {
  return SharesAtLeast(outline, crop, outline, min_fraction);
}

bool OutlineCoversBox(const PixelBox& outline, const PixelBox& box, double min_fraction) {
  return SharesAtLeast(outline, box, box, min_fraction);
}

void PerceptionOptions::Validate(const std::string& source, const std::string& prefix) const {
  const FieldCheck Require{source, prefix};
  track.Validate(source, prefix + "track.");
  segment.Validate(source, prefix + "segment.");
  self_filter.Validate(source, prefix + "self_filter.");
  Require(min_detection_score > 0.0f && min_detection_score < 1.0f, "min_detection_score",
          "must be in (0, 1)");
  Require(box_margin >= 0.0 && box_margin <= 2.0, "box_margin", "must be in [0, 2]");
  Require(near_centre_quantile >= 0.0 && near_centre_quantile <= 0.5, "near_centre_quantile",
          "must be in [0, 0.5]");
  Require(min_support_ratio > 0.0 && min_support_ratio <= 1.0, "min_support_ratio",
          "must be in (0, 1]");
  Require(min_coverage > 0.0 && min_coverage <= 1.0, "min_coverage", "must be in (0, 1]");
  Require(min_box_overlap >= 0.0 && min_box_overlap <= 1.0, "min_box_overlap", "must be in [0, 1]");
  Require(min_box_cover >= 0.0 && min_box_cover <= 1.0, "min_box_cover", "must be in [0, 1]");
  Require(min_cloud_points >= 10, "min_cloud_points", "must be >= 10");
  Require(min_global_range_m >= 0.0 && min_global_range_m < max_global_range_m,
          "min_global_range_m", "must be in [0, max_global_range_m) m");
  Require(max_global_range_m <= 10.0, "max_global_range_m", "must be at most 10 m");
  Require(reacquire_radius_m > 0.0 && reacquire_radius_m <= 10.0, "reacquire_radius_m",
          "must be in (0, 10] m");
  Require(reacquire_speed_mps >= 0.0 && reacquire_speed_mps <= 10.0, "reacquire_speed_mps",
          "must be in [0, 10] m/s");
  Require(measurement_position_std_m > 0.0, "measurement_position_std_m", "must be > 0");
  Require(weak_direction_std_m >= 0.0 && weak_direction_std_m <= 1.0, "weak_direction_std_m",
          "must be in [0, 1] m");
  Require(weak_direction_min_drop >= 0 && weak_direction_min_drop <= 100000,
          "weak_direction_min_drop", "must be in [0, 100000] points");
  Require(measurement_rotation_std_rad > 0.0, "measurement_rotation_std_rad", "must be > 0");
  Require(icp.max_iterations >= 1 && icp.max_iterations <= 100, "icp.max_iterations",
          "must be in [1, 100]");
  Require(icp.start_distance_m >= icp.end_distance_m && icp.end_distance_m > 0.0,
          "icp.end_distance_m", "must be in (0, start_distance_m]");
  Require(icp.start_distance_m < model.margin_m, "icp.start_distance_m",
          "must be below model.margin_m");
  Require(icp.min_normal_cos >= -1.0 && icp.min_normal_cos <= 1.0, "icp.min_normal_cos",
          "must be in [-1, 1]");
  Require(icp.min_normal_cos_without_color >= -1.0 && icp.min_normal_cos_without_color <= 1.0,
          "icp.min_normal_cos_without_color", "must be in [-1, 1]");
  Require(icp.max_color_distance > 0.0, "icp.max_color_distance", "must be > 0");
  Require(cloud.target_points >= 50, "cloud.target_points", "must be >= 50");
  Require(cloud.min_depth_m > 0.0 && cloud.max_depth_m > cloud.min_depth_m, "cloud.max_depth_m",
          "must be above cloud.min_depth_m > 0");
  Require(ekf.gate_nis > 0.0, "ekf.gate_nis", "must be > 0");
  Require(gated_frames_to_reset >= 1, "gated_frames_to_reset", "must be >= 1");
  Require(detect_every_frames >= 1 && detect_every_frames <= 30, "detect_every_frames",
          "must be in [1, 30]");
  Require(frames_without_box_to_search_frame >= 0 && frames_without_box_to_search_frame <= 1000,
          "frames_without_box_to_search_frame", "must be in [0, 1000] frames (0: never)");
  Require(lost_search_every_frames >= 1 && lost_search_every_frames <= 30,
          "lost_search_every_frames", "must be in [1, 30] frames");
  Require(whole_frame_points >= 50 && whole_frame_points <= 100000, "whole_frame_points",
          "must be in [50, 100000]");
  Require(weak_direction_ratio >= 0.0 && weak_direction_ratio <= 1.0, "weak_direction_ratio",
          "must be in [0, 1]");
  // The stages' own options (their headers document these bounds).
  Require(model.spacing_m >= 0.001 && model.spacing_m <= 0.05, "model.spacing_m",
          "must be in [0.001, 0.05] m");
  Require(model.cell_m >= 0.001 && model.cell_m <= 0.05, "model.cell_m",
          "must be in [0.001, 0.05] m");
  Require(model.margin_m > 0.0 && model.margin_m <= 0.5, "model.margin_m", "must be in (0, 0.5] m");
  Require(cloud.target_points <= 100000, "cloud.target_points", "must be at most 100000");
  Require(cloud.normal_radius_m > 0.0, "cloud.normal_radius_m", "must be > 0 m");
  Require(cloud.max_normal_jump_m > 0.0, "cloud.max_normal_jump_m", "must be > 0 m");
  Require(icp.depth_noise_per_m2 >= 0.0, "icp.depth_noise_per_m2", "must be >= 0 (1/m)");
  Require(icp.point_to_point_weight >= 0.0 && icp.point_to_point_weight <= 1.0,
          "icp.point_to_point_weight", "must be in [0, 1]");
  Require(icp.damping >= 0.0, "icp.damping", "must be >= 0");
  Require(icp.converged_step_m >= 0.0, "icp.converged_step_m", "must be >= 0 m");
  Require(icp.min_inliers >= 6, "icp.min_inliers",
          "must be >= 6 (a pose has 6 degrees of freedom)");
  Require(global.voxel_m > 0.0, "global.voxel_m", "must be > 0 m");
  Require(global.feature_radius_m > 0.0, "global.feature_radius_m", "must be > 0 m");
  Require(global.max_iterations >= 1 && global.max_iterations <= 100000, "global.max_iterations",
          "must be in [1, 100000]");
  Require(global.attempts >= 0 && global.attempts <= 20, "global.attempts",
          "must be in [0, 20] (0: no feature matching)");
  Require(global.work_per_frame >= 0 && global.work_per_frame <= 1000000000,
          "global.work_per_frame", "must be in [0, 1e9] pairings (0: no bound)");
  Require(global.attempts == 0 || global.work_per_frame == 0, "global.attempts",
          "must be 0 when global.work_per_frame bounds the search (feature matching's cost has "
          "no bound)");
  Require(global.orientations >= 0 && global.orientations <= 1000, "global.orientations",
          "must be in [0, 1000] (0: off)");
  Require(global.refined_orientations >= 0 && global.refined_orientations <= 100,
          "global.refined_orientations", "must be in [0, 100]");
  Require(global.inlier_fraction >= 0.0 && global.inlier_fraction <= 1.0, "global.inlier_fraction",
          "must be in [0, 1]");
  Require(ekf.accel_noise_mps2 > 0.0, "ekf.accel_noise_mps2", "must be > 0 m/s^2");
  Require(ekf.angular_accel_noise_radps2 > 0.0, "ekf.angular_accel_noise_radps2",
          "must be > 0 rad/s^2");
  Require(ekf.init_position_std_m > 0.0, "ekf.init_position_std_m", "must be > 0 m");
  Require(ekf.init_rotation_std_rad > 0.0, "ekf.init_rotation_std_rad", "must be > 0 rad");
  Require(ekf.init_velocity_std_mps > 0.0, "ekf.init_velocity_std_mps", "must be > 0 m/s");
  Require(ekf.init_angular_velocity_std_radps > 0.0, "ekf.init_angular_velocity_std_radps",
          "must be > 0 rad/s");
  Require(ekf.max_predict_dt_s > 0.0, "ekf.max_predict_dt_s", "must be > 0 s");
}

std::shared_ptr<const ModelCloud> BuildTrackerModel(const ObjectModel& object,
                                                    const ModelCloudOptions& options) {
  auto model = std::make_shared<ModelCloud>(BuildModelCloud(object.mesh_o, options));
  model->symmetry = object.symmetry;  // object.yaml's group when it has one
  return model;
}

ObjectTracker::ObjectTracker(const ObjectModel& object, const PerceptionOptions& options,
                             std::unique_ptr<BoxDetector> detector)
    : ObjectTracker(object, options, std::move(detector), nullptr) {}

ObjectTracker::ObjectTracker(const ObjectModel& object, const PerceptionOptions& options,
                             std::unique_ptr<BoxDetector> detector,
                             std::shared_ptr<const ModelCloud> model)
    : options_(options),
      model_(std::move(model)),
      detector_(std::move(detector)),
      ekf_(options.ekf),
      monitor_(options.track) {
  options_.Validate("perception options", "perception.");
  if (!model_) model_ = BuildTrackerModel(object, options_.model);
  min_half_extent_m_ = 0.5 * object.dimensions_m.minCoeff();
  if (!(min_half_extent_m_ > 0.0))
    min_half_extent_m_ = 0.5 * (object.mesh_o.BoundsMax() - object.mesh_o.BoundsMin()).minCoeff();
  global_ = std::make_unique<GlobalRegistration>(*model_, options_.global);
}

ObjectTracker::~ObjectTracker() = default;

void ObjectTracker::SetInitialPose(const Eigen::Isometry3d& cMo) {
  initial_cMo_ = cMo;
  ekf_.Reset();
  EndSearch(SearchEnd::kAbandoned);
}

void ObjectTracker::ForgetColorsInBox(const Eigen::Isometry3d& oMb,
                                      const Eigen::Vector3d& half_extents_m) {
  // The model may be shared with other trackers: this one's becomes its own copy.
  auto model = std::make_shared<ModelCloud>(*model_);
  aerograsp::ForgetColorsInBox(model.get(), oMb, half_extents_m);
  model_ = std::move(model);
  global_ = std::make_unique<GlobalRegistration>(*model_, options_.global);
}

std::optional<Eigen::Vector3d> ObjectTracker::EstimateCentre(const PixelBox& box,
                                                             const DepthImage& depth,
                                                             double depth_scale_m,
                                                             const CameraIntrinsics& K,
                                                             double quantile) const {
  // The median (or the given quantile) of the depths in the box's inner half is
  // on the object's surface; the centre lies about the smallest half-extent behind it.
  const PixelBox inner = box.Grown(-0.25).Clipped(depth.width, depth.height);
  std::vector<std::uint16_t> values;
  for (int y = inner.y0; y < inner.y1; y += 2) {
    for (int x = inner.x0; x < inner.x1; x += 2) {
      if (depth.at(x, y) > 0) values.push_back(depth.at(x, y));
    }
  }
  if (values.size() < 10) return std::nullopt;
  const std::size_t k =
      std::min(values.size() - 1, static_cast<std::size_t>(quantile * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  const double z = values[k] * depth_scale_m;
  const Eigen::Vector3d ray =
      K.Unproject(0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1), 1.0).normalized();
  return ray * (z / ray.z() + min_half_extent_m_);
}

IcpResult ObjectTracker::Register(const SceneCloud& cloud, const ColorImage& color,
                                  const DepthImage& depth, double depth_scale_m,
                                  const CameraIntrinsics& K, const Eigen::Isometry3d& cMo,
                                  double slide_range_m, int* outline_drop) const {
  IcpResult icp = RefinePoseIcp(*model_, cloud, cMo, frame_icp_);
  *outline_drop = -1;
  if (icp.ok && icp.weak_ratio < options_.weak_direction_ratio) {
    // The pairs leave a sliding direction: let the outline in the depth image decide it.
    const DepthImage* arms =
        arms_in_depth_ && options_.self_filter.in_slide ? &filtered_depth_ : nullptr;
    SlideFit slid =
        SlideToBestSupport(*model_, icp.cMo, icp.weak_direction_o, color, depth, depth_scale_m, K,
                           SupportOptions(), slide_range_m, 0.001, 0.01, arms);
    // A short (tracking) slide that the outline supports less than a probe
    // beyond it: the object lies farther along (a drift the filter's velocity
    // fed while its ends were hidden); the full range finds it.
    if (slid.drop < 0 && slide_range_m < kFullSlideM) {
      slid = SlideToBestSupport(*model_, slid.cMo, icp.weak_direction_o, color, depth,
                                depth_scale_m, K, SupportOptions(), kFullSlideM, 0.001, 0.01, arms);
    }
    *outline_drop = slid.drop;
    if (!slid.cMo.isApprox(icp.cMo)) {
      const IcpResult again = RefinePoseIcp(*model_, cloud, slid.cMo, frame_icp_);
      if (again.ok) icp = again;
    }
  }
  return icp;
}

PoseSupportOptions ObjectTracker::SupportOptions() const {
  PoseSupportOptions support;
  support.depth_noise_per_m2 = frame_icp_.depth_noise_per_m2;
  support.max_color_distance = frame_icp_.max_color_distance;
  return support;
}

PoseSupport ObjectTracker::Support(const Eigen::Isometry3d& cMo, const ColorImage& color,
                                   const DepthImage& depth, double depth_scale_m,
                                   const CameraIntrinsics& K) const {
  return ScorePoseSupport(
      *model_, cMo, color, depth, depth_scale_m, K, SupportOptions(),
      arms_in_depth_ && options_.self_filter.in_support ? &filtered_depth_ : nullptr);
}

bool ObjectTracker::ExplainsDepth(const PoseSupport& support) const {
  return support.projected >= 20 && support.ratio() >= options_.min_support_ratio &&
         support.coverage() >= options_.min_coverage;
}

bool ObjectTracker::OutsideBox(const PoseSupport& support, const FrameReport& report) const {
  return report.detection && ExplainsDepth(support) &&
         (!OutlineInCrop(support.agree_box, report.crop, options_.min_box_overlap) ||
          !OutlineCoversBox(support.agree_box, report.detection->box, options_.min_box_cover));
}

bool ObjectTracker::Passes(const PoseSupport& support, const FrameReport& report) const {
  return ExplainsDepth(support) && !OutsideBox(support, report);
}

void ObjectTracker::ForgetTrack() {
  ekf_.Reset();
  monitor_.Reset();
  last_good_fMo_.reset();
  reacquire_zone_c_.reset();
  gated_in_a_row_ = 0;
}

bool ObjectTracker::Measure(const SceneCloud& cloud, const ColorImage& color,
                            const DepthImage& depth, double depth_scale_m,
                            const CameraIntrinsics& K, const std::optional<Eigen::Isometry3d>& seed,
                            const std::vector<Eigen::Vector3d>& centres_c, bool allow_global,
                            bool segment, std::size_t kept_centres, bool own_track,
                            FrameReport* report) {
  const double t0 = ThreadCpuMs();
  if (seed) {
    // Tracking: the prediction is close, a short slide search will do.
    const double slide_m =
        ekf_.initialized() && monitor_.state() == TrackState::kFound ? 0.004 : kFullSlideM;
    const IcpResult icp =
        Register(cloud, color, depth, depth_scale_m, K, *seed, slide_m, &report->outline_drop);
    report->icp = icp;
    if (icp.ok) {
      report->support = Support(icp.cMo, color, depth, depth_scale_m, K);
      if (Passes(report->support, *report)) {
        report->times.icp_ms = ThreadCpuMs() - t0;
        return true;
      }
      if (own_track && OutsideBox(report->support, *report)) {
        // The track follows a look-alike beside the detected object: forgotten,
        // the frames without a box cannot find it again from its last pose, and
        // this box is searched (at a range it can succeed at) without the
        // re-find distance around it.
        ForgetTrack();
        report->forgot_track = true;
        allow_global = !centres_c.empty();
      }
    }
  }
  report->times.icp_ms = ThreadCpuMs() - t0;
  if (!allow_global) return false;
  return Search(cloud, color, depth, depth_scale_m, K, centres_c, segment, kept_centres, report);
}

bool ObjectTracker::Search(const SceneCloud& cloud, const ColorImage& color,
                           const DepthImage& depth, double depth_scale_m, const CameraIntrinsics& K,
                           const std::vector<Eigen::Vector3d>& centres_c, bool segment,
                           std::size_t kept_centres, FrameReport* report) {
  const double cpu0 = ProcessCpuMs();
  report->global_init = true;
  report->outline_drop = -1;  // the tracking attempt's, if any, is not the measurement's
  SearchState& s = search_;
  if (!s.active) {
    s = SearchState{};
    s.active = true;
    s.segment_pending = segment && options_.segment.max_surfaces > 0;
    s.whole_frame = segment;
    ++global_stats_.searches;
  }
  ++s.frames;
  ++global_stats_.frames;
  // This frame's share, plus what earlier frames saved for a step too big for one.
  const std::int64_t per_frame = options_.global.work_per_frame;
  WorkBudget budget(per_frame > 0 ? per_frame + s.saved_work : 0);
  bool blocked = false;  // a step did not fit: the search continues next frame

  // The whole frame without a detector: the pieces of the scene off its large
  // surfaces, once, on the search's first frame that pays for it.
  if (s.segment_pending) {
    if (budget.Take(SegmentWorkBound(cloud.points_c.size(), options_.segment))) {
      s.segment_pending = false;
      SceneSegments pieces =
          SegmentScene(cloud, K, model_->diameter_m, model_->box_radius_m, min_half_extent_m_,
                       frame_icp_.depth_noise_per_m2, options_.segment);
      KeepReachable(&pieces.centres_c);
      if (!pieces.centres_c.empty()) {
        s.segmented = true;
        s.foreground = std::move(pieces.foreground);
        s.centres_c.assign(centres_c.begin(),
                           centres_c.begin() + std::min(kept_centres, centres_c.size()));
        s.centres_c.insert(s.centres_c.end(), pieces.centres_c.begin(), pieces.centres_c.end());
      }
    } else {
      blocked = true;
    }
  }
  // The cloud and centres the search runs on.
  const SceneCloud& scene = s.segmented ? s.foreground : cloud;
  const std::vector<Eigen::Vector3d>& centres = s.segmented ? s.centres_c : centres_c;

  // The short ICPs of the orientation hypotheses, from where the last frame stopped.
  if (!s.hypotheses_done && !s.segment_pending) {
    // Around several centres the hypotheses are ranked by how well they
    // explain the depth (and colour) image: their ICP inliers are not
    // comparable (a centre on a large surface has more points to pair).
    const bool scored = centres.size() > 1 || s.segmented;
    // Every orientation on each centre where the centres are few: the pieces
    // of a segmented scene, the detector box's two.
    const bool every_orientation =
        s.segmented || (report->detection.has_value() && TwoCentresInBox(options_));
    const std::int64_t score_work =
        scored ? static_cast<std::int64_t>(SupportWorkBound(*model_, SupportOptions())) : 0;
    std::vector<IcpResult> tried = global_->Hypotheses(
        scene, frame_icp_, centres, s.next_hypothesis, &budget, score_work, every_orientation);
    s.next_hypothesis += tried.size();
    if (scored) {
      std::vector<double> scores(tried.size(), 0.0);
      ParallelFor(tried.size(), [&](std::size_t k) {
        if (!tried[k].ok) return;
        const PoseSupport support = ScorePoseSupport(*model_, tried[k].cMo, color, depth,
                                                     depth_scale_m, K, SupportOptions());
        scores[k] = support.ratio() * support.agree;
      });
      s.scores.insert(s.scores.end(), scores.begin(), scores.end());
    }
    for (IcpResult& r : tried) s.hypotheses.push_back(std::move(r));
    if (s.next_hypothesis >= global_->HypothesisCount(scene, centres.size(), every_orientation)) {
      s.hypotheses_done = true;
      s.candidates = global_->Best(std::move(s.hypotheses), s.scores);
      s.next_candidate = 0;
    } else {
      blocked = true;
    }
  }

  // The candidates this frame pays for, each refined on the points within the
  // object's reach of it: ICP, ICP and slide (Register), support.
  bool found = false;
  if (s.hypotheses_done) {
    const double reach_m = model_->box_radius_m + options_.model.margin_m;
    std::vector<SceneCloud> near;
    std::vector<IcpResult> starts;
    while (s.next_candidate < s.candidates.size()) {
      const IcpResult& start = s.candidates[s.next_candidate];
      if (!budget.Take(static_cast<std::int64_t>(cloud.points_c.size()))) break;
      SceneCloud local = GlobalRegistration::Near(cloud, start.cMo * model_->box_center_o, reach_m);
      const std::size_t n = local.points_c.size();
      const std::int64_t work = static_cast<std::int64_t>(
          3 * IcpWorkBound(n, frame_icp_) + SlideWorkBound(*model_, SupportOptions(), kFullSlideM) +
          SupportWorkBound(*model_, SupportOptions()));
      if (!budget.Take(work)) break;
      near.push_back(std::move(local));
      starts.push_back(start);
      ++s.next_candidate;
    }
    blocked = blocked || s.next_candidate < s.candidates.size();
    std::vector<IcpResult> refined(starts.size());
    ParallelFor(starts.size(), [&](std::size_t k) {
      refined[k] = RefinePoseIcp(*model_, near[k], starts[k].cMo, frame_icp_);
    });
    // Refined candidates and their clouds, most inliers first.
    std::vector<std::pair<IcpResult, const SceneCloud*>> ranked;
    for (std::size_t k = 0; k < refined.size(); ++k) {
      if (refined[k].ok) ranked.emplace_back(refined[k], &near[k]);
    }
    // Feature matching: only without a bound (its cost has none), once the
    // hypotheses' candidates are all in; on the whole frame only when asked.
    std::vector<SceneCloud> feature_near;
    if (!budget.bounded() && !blocked && (options_.global.whole_frame_features || !s.whole_frame)) {
      const std::vector<IcpResult> features = global_->FeatureCandidates(cloud, frame_icp_);
      feature_near.reserve(features.size());
      for (const IcpResult& r : features) {
        feature_near.push_back(
            GlobalRegistration::Near(cloud, r.cMo * model_->box_center_o, reach_m));
      }
      for (std::size_t k = 0; k < features.size(); ++k)
        ranked.emplace_back(features[k], &feature_near[k]);
    }
    std::sort(ranked.begin(), ranked.end(),
              [](const auto& a, const auto& b) { return a.first.inliers > b.first.inliers; });
    // Each candidate registered and scored alone (on all cores), then chosen in order.
    struct Registered {
      IcpResult icp;
      int outline_drop = -1;
      bool usable = false;  // registered, and inside the reacquisition zone if any
      PoseSupport support;
    };
    std::vector<Registered> registered(ranked.size());
    ParallelFor(ranked.size(), [&](std::size_t k) {
      Registered& r = registered[k];
      r.icp = Register(*ranked[k].second, color, depth, depth_scale_m, K, ranked[k].first.cMo,
                       kFullSlideM, &r.outline_drop);
      r.usable = r.icp.ok && !(reacquire_zone_c_ &&
                               (r.icp.cMo.translation() - reacquire_zone_c_->first).norm() >
                                   reacquire_zone_c_->second);
      if (r.usable) r.support = Support(r.icp.cMo, color, depth, depth_scale_m, K);
    });
    double best_score = -1.0;
    for (const Registered& r : registered) {
      if (!r.usable) continue;
      const double score = r.support.ratio() * r.support.agree;
      if (Passes(r.support, *report) && score > best_score) {
        best_score = score;
        report->icp = r.icp;
        report->support = r.support;
        report->outline_drop = r.outline_drop;
        found = true;
      }
    }
  }
  report->global_work = budget.used();
  global_stats_.work += budget.used();
  s.saved_work = blocked && budget.bounded() ? budget.left() : 0;
  if (found) {
    EndSearch(SearchEnd::kFound);
  } else if (!blocked) {
    EndSearch(SearchEnd::kExhausted);
  }
  report->times.global_ms = ProcessCpuMs() - cpu0;
  global_stats_.cpu_ms += report->times.global_ms;
  return found;
}

bool ObjectTracker::InGlobalRange(const Eigen::Vector3d& c) const {
  return c.norm() >= options_.min_global_range_m && c.norm() <= options_.max_global_range_m;
}

bool ObjectTracker::Reachable(const Eigen::Vector3d& c) const {
  return InGlobalRange(c) &&
         !(reacquire_zone_c_ && (c - reacquire_zone_c_->first).norm() >
                                    reacquire_zone_c_->second + model_->box_radius_m);
}

void ObjectTracker::KeepReachable(std::vector<Eigen::Vector3d>* centres_c) const {
  centres_c->erase(std::remove_if(centres_c->begin(), centres_c->end(),
                                  [&](const Eigen::Vector3d& c) { return !Reachable(c); }),
                   centres_c->end());
}

void ObjectTracker::EndSearch(SearchEnd end) {
  if (!search_.active) return;
  if (end == SearchEnd::kFound) ++global_stats_.found;
  if (end == SearchEnd::kExhausted) {
    ++global_stats_.exhausted;
    frames_since_failed_search_ = 0;
  }
  if (end != SearchEnd::kAbandoned)
    global_stats_.max_frames = std::max(global_stats_.max_frames, search_.frames);
  search_ = SearchState{};
}

std::vector<Eigen::Vector3d> ObjectTracker::SearchCentres(
    const FrameReport& report, const DepthImage& depth, double depth_scale_m,
    const CameraIntrinsics& K, const std::optional<Eigen::Isometry3d>& prior) const {
  std::vector<Eigen::Vector3d> centres_c;
  if (report.detection) {
    if (auto c = EstimateCentre(report.detection->box, depth, depth_scale_m, K))
      centres_c.push_back(*c);
    // A second centre behind the box's nearest depths: an object open to the
    // camera (a U seen from above) has its median depth on its far inner face,
    // and orientations placed there settle on it the wrong way up.
    if (TwoCentresInBox(options_)) {
      if (auto c = EstimateCentre(report.detection->box, depth, depth_scale_m, K,
                                  options_.near_centre_quantile))
        centres_c.push_back(*c);
    }
    return centres_c;
  }
  // The last known place first; on the whole frame, then the rest of it, nearest first.
  if (prior) centres_c.push_back(*prior * model_->box_center_o);
  if (report.crop.width() != depth.width || report.crop.height() != depth.height) return centres_c;
  // A grid of boxes over the frame.
  std::vector<Eigen::Vector3d> grid;
  const int nx = 6, ny = 4;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int w = report.crop.width() / nx, h = report.crop.height() / ny;
      const PixelBox cell{report.crop.x0 + i * w, report.crop.y0 + j * h,
                          report.crop.x0 + (i + 1) * w, report.crop.y0 + (j + 1) * h};
      if (auto c = EstimateCentre(cell.Grown(0.5), depth, depth_scale_m, K)) grid.push_back(*c);
    }
  }
  if (prior) {
    // Only where a re-found pose may lie.
    if (reacquire_zone_c_) {
      const double reach_m = reacquire_zone_c_->second + model_->box_radius_m;
      grid.erase(std::remove_if(grid.begin(), grid.end(),
                                [&](const Eigen::Vector3d& c) {
                                  return (c - reacquire_zone_c_->first).norm() > reach_m;
                                }),
                 grid.end());
    }
    const Eigen::Vector3d last = centres_c.front();
    std::stable_sort(grid.begin(), grid.end(),
                     [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
                       return (a - last).norm() < (b - last).norm();
                     });
  }
  centres_c.insert(centres_c.end(), grid.begin(), grid.end());
  return centres_c;
}

void ObjectTracker::SetRobot(const Platform& platform) {
  self_filter_.reset();
  if (options_.self_filter.enabled)
    self_filter_ = std::make_unique<RobotSelfFilter>(platform, options_.self_filter);
  robot_dMc_ = platform.dMc();
}

FrameReport ObjectTracker::Process(const ColorImage& color, const DepthImage& camera_depth,
                                   double stamp_s, const CameraIntrinsics& K, double depth_scale_m,
                                   const std::optional<Eigen::Isometry3d>& wMc,
                                   const std::optional<ArmJointPositions>& arm_joints) {
  FrameReport report;
  const double t_start = ThreadCpuMs();
  // The arms' own pixels out of the depth, before anything uses it; or only
  // out of what the support check counts as the object's occluders.
  const bool self_filtered = self_filter_ && arm_joints;
  if (self_filtered) {
    filtered_depth_ = camera_depth;
    report.self_filter =
        self_filter_->Apply(*arm_joints, robot_dMc_, K, depth_scale_m, &filtered_depth_);
    report.times.self_filter_ms = ThreadCpuMs() - t_start;
  }
  arms_in_depth_ = self_filtered && !options_.self_filter.drop_from_depth;
  const DepthImage& depth = self_filtered && !arms_in_depth_ ? filtered_depth_ : camera_depth;
  // The cloud ICP pairs: without the arms' pixels also when they stay in the depth, if asked.
  const DepthImage& cloud_depth =
      arms_in_depth_ && options_.self_filter.drop_from_cloud ? filtered_depth_ : depth;
  // The filter frame f: the world when the camera's pose is given, else the camera.
  const Eigen::Isometry3d fMc =
      wMc && wMc->matrix().allFinite() ? *wMc : Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d cMf = fMc.inverse();
  // The stereo depth noise grows as the depth image's focal length in pixels
  // shrinks: the options give it for a 640-pixel-wide image.
  constexpr double kNoiseReferenceWidthPx = 640.0;
  frame_icp_ = options_.icp;
  if (depth.width > 0) frame_icp_.depth_noise_per_m2 *= kNoiseReferenceWidthPx / depth.width;
  const bool input_ok = !color.empty() && !depth.empty() && color.width == depth.width &&
                        color.height == depth.height && depth.width == K.width &&
                        depth.height == K.height && depth_scale_m > 0.0 && std::isfinite(stamp_s);
  if (ekf_.initialized()) ekf_.Predict(stamp_s);
  frames_since_failed_search_ = std::min(frames_since_failed_search_ + 1, kNoFailedSearch);

  // Detection: every frame until the track is found, then every
  // detect_every_frames frames while it is measured (the prediction's outline
  // crops the frames between).
  const bool tracked =
      ekf_.initialized() && monitor_.state() == TrackState::kFound && last_measured_;
  ++frames_since_detection_;
  if (detector_ && input_ok &&
      (!tracked || frames_since_detection_ >= options_.detect_every_frames)) {
    const double t_detect = ThreadCpuMs();
    frames_since_detection_ = 0;
    const std::vector<Detection> detections =
        detector_->Detect(color, options_.min_detection_score);
    if (!detections.empty()) report.detection = detections.front();
    report.times.detect_ms = ThreadCpuMs() - t_detect;
    if (report.detection) {
      // The box wins again: a whole-frame search under way is dropped.
      if (search_.active && search_.whole_frame) EndSearch(SearchEnd::kAbandoned);
      frames_without_box_ = 0;
    } else {
      ++frames_without_box_;
    }
  }
  // A detector that has found nothing for a while: the whole frame, as without one.
  const bool whole_frame_fallback =
      detector_ && options_.frames_without_box_to_search_frame > 0 &&
      frames_without_box_ >= options_.frames_without_box_to_search_frame;

  // The prior: the filter's prediction, else a given first pose, else the last good pose.
  std::optional<Eigen::Isometry3d> prior;
  if (ekf_.initialized()) {
    prior = cMf * ekf_.fMo();
  } else if (initial_cMo_) {
    prior = initial_cMo_;
  } else if (last_good_fMo_) {
    prior = cMf * *last_good_fMo_;
  }
  // The track's own pose (not a given one) seeds this frame: a pose measured
  // from it continues the track.
  const bool own_prior = ekf_.initialized() || (!initial_cMo_ && last_good_fMo_);
  reacquire_zone_c_.reset();
  if (was_found_ && last_good_fMo_ && !initial_cMo_) {
    const double since_s = std::max(0.0, stamp_s - last_good_stamp_s_);
    reacquire_zone_c_.emplace(cMf * last_good_fMo_->translation(),
                              options_.reacquire_radius_m + options_.reacquire_speed_mps * since_s);
  }

  // Crop and cloud.
  double t = ThreadCpuMs();
  SceneCloud cloud;
  if (input_ok) {
    if (report.detection) {
      report.crop = report.detection->box.Grown(options_.box_margin);
    } else if (ekf_.initialized()) {
      report.crop = ScorePoseSupport(*model_, *prior, {}, depth, depth_scale_m, K)
                        .box.Grown(options_.box_margin);
    } else if (!detector_ || whole_frame_fallback || initial_cMo_) {
      report.crop = initial_cMo_
                        ? ScorePoseSupport(*model_, *initial_cMo_, {}, depth, depth_scale_m, K)
                              .box.Grown(options_.box_margin)
                        : PixelBox{0, 0, depth.width, depth.height};
    }
    report.crop = report.crop.Clipped(depth.width, depth.height);
    SceneCloudOptions cloud_options = options_.cloud;
    if (report.crop.width() == depth.width && report.crop.height() == depth.height) {
      // The whole frame (no detector, no prior): denser, the object is a small part of it.
      cloud_options.target_points =
          std::max(cloud_options.target_points, options_.whole_frame_points);
    }
    if (!report.crop.empty())
      cloud = BuildSceneCloud(color, cloud_depth, depth_scale_m, K, report.crop, cloud_options);
  }
  report.cloud_points = static_cast<int>(cloud.points_c.size());
  report.times.cloud_ms = ThreadCpuMs() - t;

  // Pose measurement.
  if (report.cloud_points >= options_.min_cloud_points) {
    // A search under way goes on; a new one waits lost_search_every_frames
    // after one that found nothing.
    bool allow_global =
        !initial_cMo_ && (!ekf_.initialized() || monitor_.state() == TrackState::kLost) &&
        (search_.active || frames_since_failed_search_ >= options_.lost_search_every_frames);
    // Where the object may be, for the global registration's orientation hypotheses.
    std::vector<Eigen::Vector3d> centres_c = SearchCentres(report, depth, depth_scale_m, K, prior);
    const bool whole_frame =
        report.crop.width() == depth.width && report.crop.height() == depth.height;
    const bool segment = whole_frame && !report.detection;
    // The last known place leads the centres (SearchCentres) and stays first
    // when the search segments the scene.
    std::size_t kept_centres =
        segment && prior && !centres_c.empty() && InGlobalRange(centres_c.front()) ? 1 : 0;
    // Only where the object may be, at a range where the search can succeed.
    const std::size_t centres = centres_c.size();
    centres_c.erase(std::remove_if(centres_c.begin(), centres_c.end(),
                                   [&](const Eigen::Vector3d& c) { return !InGlobalRange(c); }),
                    centres_c.end());
    // (A segmented search finds its own centres.)
    if (centres > 0 && centres_c.empty() && !segment) allow_global = false;
    // A detector's box whose centres all lie beyond the reacquisition zone
    // holds no pose the search may return (a forgotten track's search has no
    // zone: Measure).
    if (report.detection && allow_global && !centres_c.empty()) {
      allow_global = std::any_of(centres_c.begin(), centres_c.end(),
                                 [&](const Eigen::Vector3d& c) { return Reachable(c); });
    }
    // A pose of the track's own that lies outside the detector's crop, or
    // does not cover its box, forgets the track (Measure), when the box check is on.
    const bool own_track =
        own_prior && (options_.min_box_overlap > 0.0 || options_.min_box_cover > 0.0);
    report.measured = Measure(cloud, color, depth, depth_scale_m, K, prior, centres_c, allow_global,
                              segment, kept_centres, own_track, &report);
  }

  // A track measured from its prior needs no search.
  if (report.measured && !report.global_init) EndSearch(SearchEnd::kAbandoned);

  // Filter.
  t = ThreadCpuMs();
  if (report.measured) {
    Eigen::Isometry3d meas = report.icp.cMo;
    const double z = std::max(0.1, meas.translation().z());
    const double sp = options_.measurement_position_std_m * std::max(0.25, z * z);
    const double sr = options_.measurement_rotation_std_rad * std::max(0.5, z);
    Eigen::Matrix<double, 6, 6> R = Eigen::Matrix<double, 6, 6>::Zero();
    R.diagonal() << sp * sp, sp * sp, sp * sp, sr * sr, sr * sr, sr * sr;
    if (report.icp.weak_ratio < options_.weak_direction_ratio &&
        options_.weak_direction_std_m > 0.0) {
      const Eigen::Vector3d u_c = (meas.linear() * report.icp.weak_direction_o).normalized();
      R.topLeftCorner<3, 3>() +=
          options_.weak_direction_std_m * options_.weak_direction_std_m * u_c * u_c.transpose();
    }
    // Into the filter frame (positions and left rotation errors both turn with fRc).
    meas = fMc * meas;
    Eigen::Matrix<double, 6, 6> fRc6 = Eigen::Matrix<double, 6, 6>::Zero();
    fRc6.topLeftCorner<3, 3>() = fMc.linear();
    fRc6.bottomRightCorner<3, 3>() = fMc.linear();
    R = fRc6 * R * fRc6.transpose();
    if (!ekf_.initialized()) {
      ekf_.Initialize(meas, stamp_s);
      gated_in_a_row_ = 0;
    } else {
      meas = WithSymmetricRotation(
          meas, ClosestSymmetricRotation(meas.linear(), ekf_.fMo().linear(), model_->symmetry),
          model_->symmetry);
      const EkfUpdate update = ekf_.Update(meas, R);
      report.nis = update.nis;
      if (update.accepted) {
        gated_in_a_row_ = 0;
      } else {
        report.gated = true;
        if (++gated_in_a_row_ >= options_.gated_frames_to_reset) {
          ekf_.Initialize(meas, stamp_s);
          gated_in_a_row_ = 0;
        }
      }
    }
    last_good_fMo_ = ekf_.fMo();
    last_good_stamp_s_ = stamp_s;
  }
  // A given first pose serves this frame only, measured or not: kept, it
  // would forbid the global registration for good once the object has moved
  // away from it (the mission then never found a lost object again).
  initial_cMo_.reset();
  last_measured_ = report.measured;
  const double confidence = report.measured ? std::min(1.0, report.support.ratio()) *
                                                  std::min(1.0, report.support.coverage() / 0.5) *
                                                  (report.gated ? 0.5 : 1.0)
                                            : 0.0;
  const bool continues = was_found_ && own_prior && report.measured && !report.global_init;
  const TrackState state = monitor_.Update(confidence, continues);
  was_found_ = was_found_ || state == TrackState::kFound;
  if (state == TrackState::kLost && !report.measured && ekf_.initialized()) {
    // Lost and nothing seen: drop the filter (a stale velocity must not carry the
    // pose away); the last good pose seeds the next attempt.
    if (monitor_.state() == TrackState::kLost && confidence == 0.0) ekf_.Reset();
  }
  report.times.filter_ms = ThreadCpuMs() - t;

  ObjectEstimate& e = report.estimate;
  e.stamp_s = stamp_s;
  e.confidence = confidence;
  e.state = state;
  e.weak_direction_fixed = report.measured && !report.gated &&
                           (report.icp.weak_ratio >= options_.weak_direction_ratio ||
                            report.outline_drop >= options_.weak_direction_min_drop);
  if (ekf_.initialized()) {
    e.valid = true;
    e.fMo = ekf_.fMo();
    e.covariance = ekf_.covariance().topLeftCorner<6, 6>();  // in f
    e.v_f = ekf_.v_f();
    e.v_c = cMf.linear() * ekf_.v_f();
    e.w_c = cMf.linear() * ekf_.w_f();
  } else if (last_good_fMo_) {
    e.valid = true;
    e.fMo = *last_good_fMo_;
  }
  e.cMo = cMf * e.fMo;
  report.times.total_ms = ThreadCpuMs() - t_start;
  return report;
}

}  // namespace aerograsp
