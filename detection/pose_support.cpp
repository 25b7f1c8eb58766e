#include "detection/pose_support.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <utility>
#include <vector>

#include "detection/icp.h"

namespace aerograsp {
namespace {

/// The slide search scores at least this many model points (a slide of a few
/// mm moves only the points at the ends).
constexpr int kSlidePoints = 2000;

/// Model points nearer to the camera than this (m, along its axis) are not scored.
constexpr float kMinDepthM = 0.05f;

/// Whether the model hides its own point i from the camera at c_o (frame o):
/// marching from the point towards the camera, the ray meets the model's
/// surface well above the point's own tangent plane (a track beside the body,
/// taller than it). Front-facing points can be hidden so; when the hiding part
/// is nearer by less than the depth tolerance (15 mm against 32 mm at 1.5 m),
/// their depth agrees and their colour is the hiding part's. Only where the
/// noise widens the tolerance beyond its floor: nearer, such a strip is
/// occluded by depth alone, and a colour that disagrees there is something
/// else in front of the object (a gripper's fingers).
bool SelfOccluded(const ModelCloud& model, std::size_t i, const Eigen::Vector3f& c_o) {
  const Eigen::Vector3f& p = model.points_o[i];
  const Eigen::Vector3f& n = model.normals_o[i];
  const Eigen::Vector3f to_camera = c_o - p;
  const float range = std::min(to_camera.norm(), static_cast<float>(model.diameter_m));
  const Eigen::Vector3f d = to_camera.normalized();
  const float step = model.cell_m, near = 2.0f * model.cell_m;
  for (float s = 2.0f * step; s <= range; s += step) {
    const int j = model.Nearest(p + s * d);
    if (j < 0) return false;  // left the model's grid: nothing above
    const Eigen::Vector3f& q = model.points_o[j];
    if ((q - (p + s * d)).squaredNorm() <= near * near && n.dot(q - p) > near) return true;
  }
  return false;
}

/// std::lround for the pixel coordinates (|x| far below 2^52): the same
/// result without the library call (half-way cases away from zero).
long RoundHalfAway(double x) {
  const long r = static_cast<long>(x);  // towards zero; x - r is exact
  const double rest = x - static_cast<double>(r);
  return rest >= 0.5 ? r + 1 : (rest <= -0.5 ? r - 1 : r);
}

/// The model points a scorer samples: about 2 * max_points, strided (about
/// half face the camera).
std::size_t SampleStride(std::size_t model_points, int max_points) {
  return std::max<std::size_t>(1, model_points / std::max(1, 2 * max_points));
}

/// The slide search's fine step and its coarse step (4 fine steps), m.
std::pair<double, double> SlideSteps(double step_m) {
  const double fine_m = std::max(1e-4, step_m);
  return {fine_m, 4.0 * fine_m};
}

/// The support of cMo and of poses translated from it: the strided model
/// points and normals are put in the camera frame once, so a translated pose
/// costs a projection per point (the slide search scores a dozen of them).
class SupportScorer {
 public:
  SupportScorer(const ModelCloud& model, const Eigen::Isometry3d& cMo, const ColorImage& color,
                const DepthImage& depth, double depth_scale_m, const CameraIntrinsics& K,
                const PoseSupportOptions& options, const DepthImage* arms_dropped = nullptr)
      : model_(model),
        color_(color),
        depth_(depth),
        arms_dropped_(arms_dropped && arms_dropped->width == depth.width &&
                              arms_dropped->height == depth.height && !arms_dropped->empty()
                          ? arms_dropped
                          : nullptr),
        depth_scale_m_(depth_scale_m),
        K_(K),
        options_(options) {
    check_color_ = model.has_colors() && options.max_color_distance < 768.0 &&
                   color.width == depth.width && color.height == depth.height && !color.empty();
    valid_ = !model.points_o.empty() && !depth.empty() && cMo.matrix().allFinite() &&
             depth_scale_m > 0.0;
    if (!valid_) return;
    const Eigen::Isometry3f cMo_f = cMo.cast<float>();
    cRo_ = cMo_f.linear();
    t_c_ = cMo_f.translation();
    const std::size_t n = model.points_o.size();
    const std::size_t step = SampleStride(n, options.max_points);
    for (std::size_t i = 0; i < n; i += step) {
      index_.push_back(i);
      p_c_.push_back(cMo_f * model.points_o[i]);
      n_c_.push_back(cRo_ * model.normals_o[i]);
      if (check_color_) {
        unit_rgb_.push_back(model.color_known(i) ? BrightnessNormalized(model.colors[i])
                                                 : Eigen::Vector3f::Constant(-1.0f));
      }
    }
  }

  /// Keeps the samples Score may count at cMo translated by up to
  /// max_offset_m times direction_c: those that face away from the
  /// camera, or lie behind it, at every such pose are dropped (by a margin
  /// far above float rounding, so Score skips each of them there anyway), and
  /// the rest are ordered facing the camera at cMo first. Score's counts and
  /// box do not depend on the samples' order: the same support, with fewer
  /// samples visited and fewer mispredicted branches.
  void KeepFacing(const Eigen::Vector3d& direction_c, double max_offset_m) {
    constexpr double kMarginM = 1e-4;  // against about 1e-6 m of float rounding at a few metres
    std::vector<std::size_t> order;
    std::vector<std::size_t> away;
    for (std::size_t k = 0; k < index_.size(); ++k) {
      const Eigen::Vector3d p = p_c_[k].cast<double>(), n = n_c_[k].cast<double>();
      const double facing_min = n.dot(p) - std::abs(n.dot(direction_c)) * max_offset_m;
      const double z_max = p.z() + std::abs(direction_c.z()) * max_offset_m;
      if (facing_min > kMarginM || z_max < kMinDepthM - kMarginM) continue;
      (n_c_[k].dot(p_c_[k]) < 0.0f ? order : away).push_back(k);
    }
    order.insert(order.end(), away.begin(), away.end());
    std::vector<std::size_t> index;
    std::vector<Eigen::Vector3f> p_c, n_c, unit_rgb;
    for (const std::size_t k : order) {
      index.push_back(index_[k]);
      p_c.push_back(p_c_[k]);
      n_c.push_back(n_c_[k]);
      if (check_color_) unit_rgb.push_back(unit_rgb_[k]);
    }
    index_ = std::move(index);
    p_c_ = std::move(p_c);
    n_c_ = std::move(n_c);
    unit_rgb_ = std::move(unit_rgb);
  }

  /// Whether the surface seen at pixel (u, v), z_obs m deep, is the model's
  /// own at cMo translated by shift_c: within the tolerance's floor
  /// (min_tolerance_m) of a model point. A front-facing point behind it is
  /// hidden by the object itself (the far inner wall of a pipe, a part behind
  /// another), not by something in front of the object: it is not part of the
  /// visible model. Only the floor: far away, where the depth noise widens the
  /// tolerance to centimetres, a larger surface near a wrong pose (the support
  /// pipe around a pose inside it) would pass for the model's own.
  bool HiddenByModel(int u, int v, double z_obs, const Eigen::Vector3f& shift_c) const {
    const float tolerance_m = static_cast<float>(options_.min_tolerance_m);
    const Eigen::Vector3f seen_c = K_.Unproject(u, v, z_obs).cast<float>();
    const Eigen::Vector3f seen_o = cRo_.transpose() * (seen_c - t_c_ - shift_c);
    const int j = model_.Nearest(seen_o);
    return j >= 0 && (model_.points_o[j] - seen_o).squaredNorm() <= tolerance_m * tolerance_m;
  }

  /// ColorDistance from the colour at pixel (u, v) to a colour given
  /// BrightnessNormalized (the same float).
  float ColorDistanceTo(const Eigen::Vector3f& unit_rgb, int u, int v) const {
    const std::uint8_t* rgb = &color_.at(u, v);
    const Eigen::Vector3f seen(rgb[0], rgb[1], rgb[2]);
    return (BrightnessNormalized(seen) - unit_rgb).cwiseAbs().sum();
  }

  /// Whether the surface seen at pixel (u, v) (with depth) is the robot's own arm.
  bool SeenOnArm(int u, int v) const { return arms_dropped_ && arms_dropped_->at(u, v) == 0; }

  /// The support of cMo translated by shift_c (frame c).
  PoseSupport Score(const Eigen::Vector3f& shift_c) const {
    PoseSupport support;
    if (!valid_) return support;
    support.box = {INT_MAX, INT_MAX, INT_MIN, INT_MIN};
    support.agree_box = support.box;
    // The camera in o at the translated pose, for the self-occlusion test.
    const Eigen::Vector3f c_o = -(cRo_.transpose() * (t_c_ + shift_c));
    for (std::size_t k = 0; k < index_.size(); ++k) {
      const Eigen::Vector3f p = p_c_[k] + shift_c;
      if (p.z() < kMinDepthM || n_c_[k].dot(p) >= 0.0f) continue;
      const Eigen::Vector2d uv = K_.Project(p.cast<double>());
      const int u = static_cast<int>(RoundHalfAway(uv.x())),
                v = static_cast<int>(RoundHalfAway(uv.y()));
      if (u < 0 || v < 0 || u >= depth_.width || v >= depth_.height) continue;
      support.box.x0 = std::min(support.box.x0, u);
      support.box.y0 = std::min(support.box.y0, v);
      support.box.x1 = std::max(support.box.x1, u + 1);
      support.box.y1 = std::max(support.box.y1, v + 1);
      const std::uint16_t d = depth_.at(u, v);
      if (d == 0) continue;
      ++support.projected;
      const double z_obs = d * depth_scale_m_;
      const double tolerance =
          std::max(options_.min_tolerance_m, 3.0 * options_.depth_noise_per_m2 * p.z() * p.z());
      if (std::abs(z_obs - p.z()) <= tolerance) {
        const std::size_t i = index_[k];
        if (!check_color_ || unit_rgb_[k].x() < 0.0f ||
            ColorDistanceTo(unit_rgb_[k], u, v) <= options_.max_color_distance) {
          ++support.agree;
          support.agree_box.x0 = std::min(support.agree_box.x0, u);
          support.agree_box.y0 = std::min(support.agree_box.y0, v);
          support.agree_box.x1 = std::max(support.agree_box.x1, u + 1);
          support.agree_box.y1 = std::max(support.agree_box.y1, v + 1);
        } else if (SeenOnArm(u, v)) {
          --support.projected;  // the robot's arm hides it
          ++support.behind_arm;
        } else if (tolerance > options_.min_tolerance_m && z_obs < p.z() - 0.5 * tolerance &&
                   SelfOccluded(model_, i, c_o)) {
          --support.projected;  // a nearer part of the model hides it
        } else {
          ++support.see_through;
        }
      } else if (z_obs > p.z()) {
        ++support.see_through;
      } else if (SeenOnArm(u, v)) {
        --support.projected;  // the robot's arm hides it
        ++support.behind_arm;
      } else if (HiddenByModel(u, v, z_obs, shift_c)) {
        --support.projected;  // the model's own nearer surface hides it
      } else {
        ++support.occluded;
      }
    }
    if (support.box.x0 == INT_MAX) support.box = {};
    if (support.agree_box.x0 == INT_MAX) support.agree_box = {};
    return support;
  }

 private:
  const ModelCloud& model_;
  const ColorImage& color_;
  const DepthImage& depth_;
  const DepthImage* arms_dropped_;  // depth_ without the robot's pixels, or null
  double depth_scale_m_;
  CameraIntrinsics K_;
  PoseSupportOptions options_;
  bool check_color_ = false, valid_ = false;
  Eigen::Matrix3f cRo_ = Eigen::Matrix3f::Identity();
  Eigen::Vector3f t_c_ = Eigen::Vector3f::Zero();  // cMo's translation
  std::vector<std::size_t> index_;                 // model point of each sample
  std::vector<Eigen::Vector3f> p_c_, n_c_;         // its point and normal in c at cMo
  // Its colour BrightnessNormalized when the colour is checked (x < 0: not known).
  std::vector<Eigen::Vector3f> unit_rgb_;
};

}  // namespace

PoseSupport ScorePoseSupport(const ModelCloud& model, const Eigen::Isometry3d& cMo,
                             const ColorImage& color, const DepthImage& depth, double depth_scale_m,
                             const CameraIntrinsics& K, const PoseSupportOptions& options,
                             const DepthImage* arms_dropped) {
  SupportScorer scorer(model, cMo, color, depth, depth_scale_m, K, options, arms_dropped);
  scorer.KeepFacing(Eigen::Vector3d::UnitZ(), 0.0);
  return scorer.Score(Eigen::Vector3f::Zero());
}

std::size_t SupportWorkBound(const ModelCloud& model, const PoseSupportOptions& options) {
  const std::size_t n = model.points_o.size();
  const std::size_t step = SampleStride(n, options.max_points);
  return (n + step - 1) / step;
}

std::size_t SlideWorkBound(const ModelCloud& model, const PoseSupportOptions& options,
                           double range_m, double step_m) {
  PoseSupportOptions dense = options;
  dense.max_points = std::max(options.max_points, kSlidePoints);
  const double coarse_m = SlideSteps(step_m).second;
  // The sampling, the coarse offsets, the fine ones around the best, the two probes.
  const std::size_t scores =
      1 + (2 * static_cast<std::size_t>(std::lround(range_m / coarse_m)) + 1) + 7 + 2;
  return scores * SupportWorkBound(model, dense);
}

SlideFit SlideToBestSupport(const ModelCloud& model, const Eigen::Isometry3d& cMo,
                            const Eigen::Vector3d& direction_o, const ColorImage& color,
                            const DepthImage& depth, double depth_scale_m,
                            const CameraIntrinsics& K, const PoseSupportOptions& options,
                            double range_m, double step_m, double probe_m,
                            const DepthImage* arms_dropped) {
  // Coarse (4 fine steps) over the whole range, then fine around the best, with
  // many points: a slide of a few mm moves only the points at the ends.
  PoseSupportOptions dense = options;
  dense.max_points = std::max(options.max_points, kSlidePoints);
  const auto [fine_m, coarse_m] = SlideSteps(step_m);
  SupportScorer scorer(model, cMo, color, depth, depth_scale_m, K, dense, arms_dropped);
  const Eigen::Vector3d direction_c = cMo.linear() * direction_o;
  // The farthest slide scored: the farthest coarse offset, three fine steps
  // from it, and a probe beyond those.
  const int coarse_steps = static_cast<int>(std::lround(range_m / coarse_m));
  scorer.KeepFacing(direction_c, coarse_steps * coarse_m + 3.0 * fine_m + std::abs(probe_m));
  const auto slid = [&](double offset_m) {
    Eigen::Isometry3d candidate = cMo;
    candidate.translation() += direction_c * offset_m;
    return candidate;
  };
  // Supports by offset: the fine search starts on the coarse search's best.
  std::vector<std::pair<double, PoseSupport>> scored;
  const auto support_at = [&](double offset_m) {
    for (const auto& [offset, s] : scored) {
      if (offset == offset_m) return s;
    }
    scored.emplace_back(offset_m, scorer.Score((direction_c * offset_m).cast<float>()));
    return scored.back().second;
  };
  const auto score = [&](double offset_m) {
    const PoseSupport s = support_at(offset_m);
    return s.agree - s.see_through;
  };
  // The drop's score: a model point behind the arms' pixels may be the object
  // there, so a slide that moves the model's end under a finger loses nothing.
  const auto drop_score = [&](double offset_m) {
    const PoseSupport s = support_at(offset_m);
    return s.agree + s.behind_arm - s.see_through;
  };
  SlideFit fit;
  double best_offset_m = 0.0;
  int best_score = INT_MIN;
  auto search = [&](double centre_m, double step, int steps) {
    best_score = INT_MIN;
    // Offsets centre, +1, -1, +2, -2, ... steps: ties go to the smaller slide.
    for (int i = 0; i <= 2 * steps; ++i) {
      const double offset_m = centre_m + (i + 1) / 2 * (i % 2 ? 1 : -1) * step;
      const int s = score(offset_m);
      if (s > best_score) {
        best_score = s;
        best_offset_m = offset_m;
      }
    }
  };
  search(0.0, coarse_m, coarse_steps);
  search(best_offset_m, fine_m, 3);
  fit.cMo = slid(best_offset_m);
  fit.drop = drop_score(best_offset_m) -
             std::max(drop_score(best_offset_m - probe_m), drop_score(best_offset_m + probe_m));
  return fit;
}

}  // namespace aerograsp
