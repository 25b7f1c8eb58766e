#include "detection/icp.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/transforms.h"

namespace aerograsp {

float ColorDistance(const Eigen::Vector3f& rgb_a, const Eigen::Vector3f& rgb_b) {
  return (BrightnessNormalized(rgb_a) - BrightnessNormalized(rgb_b)).cwiseAbs().sum();
}

Rejection ClassifyPair(const Eigen::Vector3f& p, const Eigen::Vector3f& n_p,
                       const Eigen::Vector3f& rgb_p, const Eigen::Vector3f& q,
                       const Eigen::Vector3f& n_q, const Eigen::Vector3f& rgb_q,
                       const RejectorThresholds& thresholds) {
  // Eq. 1: Euclidean distance, or across and along the pixel's ray.
  const Eigen::Vector3f e = p - q;
  if (thresholds.ray.isZero()) {
    if (e.squaredNorm() > thresholds.max_distance_m * thresholds.max_distance_m)
      return Rejection::kDistance;
  } else {
    const float along = e.dot(thresholds.ray);
    if (std::abs(along) > thresholds.max_along_ray_m ||
        (e - along * thresholds.ray).squaredNorm() >
            thresholds.max_distance_m * thresholds.max_distance_m) {
      return Rejection::kDistance;
    }
  }
  // Eq. 2: cosine of the angle between the normals (a zero normal could not be fitted).
  if (thresholds.min_normal_cos > -1.0 && !n_p.isZero() &&
      n_p.dot(n_q) < thresholds.min_normal_cos) {
    return Rejection::kNormal;
  }
  // Eq. 3: L1 colour distance.
  if (thresholds.max_color_distance < 768.0 &&
      ColorDistance(rgb_p, rgb_q) > thresholds.max_color_distance) {
    return Rejection::kColor;
  }
  return Rejection::kNone;
}

namespace {

/// The model point where the ray through p (unit direction d, frame o) meets
/// the model's surface near p: from the nearest point j, a few steps to the
/// plane of the current point along the ray, at most `limit_m` from p. Returns
/// j unchanged where the ray grazes the surface.
int FollowRayToSurface(const ModelCloud& model, const Eigen::Vector3f& p, const Eigen::Vector3f& d,
                       float limit_m, int j) {
  float t = 0.0f;
  for (int step = 0; step < 3; ++step) {
    const Eigen::Vector3f& n = model.normals_o[j];
    const float along = n.dot(d);
    if (std::abs(along) < 0.3f) break;  // grazing: the plane's crossing is far off
    const float offset_m = n.dot(p + t * d - model.points_o[j]);
    if (std::abs(offset_m) < 2e-4f) break;
    const float t_next = std::clamp(t - offset_m / along, -limit_m, limit_m);
    const int j_next = model.Nearest(p + t_next * d);
    if (j_next < 0 || model.normals_o[j_next].dot(d) > 0.0f) break;
    t = t_next;
    j = j_next;
  }
  return j;
}

/// A model point whose normal faces away from the camera (along the ray d)
/// cannot have returned the depth at p: the noise pushed p behind a surface
/// that faces the camera, into a wall or through a thin part, and the nearest
/// point is the wall's inside. Returns the first point facing the camera found
/// stepping back along the ray from p and lying on it (within two grid cells),
/// at most `limit_m` back (the noise's reach; farther, the pose is wrong, as
/// where a wrong orientation puts the model's back faces on the scene's
/// surface); j when there is none.
int FrontFacingAlongRay(const ModelCloud& model, const Eigen::Vector3f& p, const Eigen::Vector3f& d,
                        float limit_m, int j) {
  if (model.normals_o[j].dot(d) <= 0.0f) return j;
  for (float t = model.cell_m; t <= limit_m; t += model.cell_m) {
    const Eigen::Vector3f on_ray = p - t * d;
    const int k = model.Nearest(on_ray);
    // On the ray: a point beside it (the ray passing an edge, the background
    // beyond the object) is not the surface that returned the depth.
    if (k >= 0 && model.normals_o[k].dot(d) < 0.0f &&
        (model.points_o[k] - on_ray).norm() <= 2.0f * model.cell_m) {
      return k;
    }
  }
  return j;
}

struct PassStats {
  int inliers = 0, no_model = 0, distance = 0, normal = 0, color = 0;
  double sum_r2 = 0.0;
  Eigen::Matrix3d normal_scatter = Eigen::Matrix3d::Zero();  // sum n n^T of the inliers (frame o)
  // The point-to-point term's sums over the inliers (frame o): p, p p^T, |p|^2,
  // p x e and e, with e = p - q. Its normal equations follow from them once.
  Eigen::Vector3d sum_p = Eigen::Vector3d::Zero(), sum_p_cross_e = Eigen::Vector3d::Zero(),
                  sum_e = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_ppT = Eigen::Matrix3d::Zero();
  double sum_p2 = 0.0;
};

/// One association pass at oMc: classifies every scene point and, when H and g
/// are given, accumulates the point-to-plane normal equations in frame o.
PassStats Associate(const ModelCloud& model, const SceneCloud& scene, const Eigen::Isometry3f& oMc,
                    double max_distance_m, const IcpOptions& options,
                    Eigen::Matrix<double, 6, 6>* H, Eigen::Matrix<double, 6, 1>* g) {
  PassStats stats;
  RejectorThresholds thresholds;
  thresholds.max_distance_m = max_distance_m;
  thresholds.min_normal_cos =
      model.has_colors() ? options.min_normal_cos : options.min_normal_cos_without_color;
  // Eq. 3 only against colour the model has: a plain mesh is paired on geometry.
  thresholds.max_color_distance = model.has_colors() ? options.max_color_distance : 768.0;
  const Eigen::Matrix3f oRc = oMc.linear();
  for (std::size_t i = 0; i < scene.points_c.size(); ++i) {
    const Eigen::Vector3f p = oMc * scene.points_c[i];
    int j = model.Nearest(p);
    if (j < 0) {
      ++stats.no_model;
      continue;
    }
    const double z = scene.points_c[i].z();
    const double noise_3sigma_m = 3.0 * options.depth_noise_per_m2 * z * z;
    const Eigen::Vector3f ray = oRc * scene.points_c[i].normalized();
    j = FrontFacingAlongRay(model, p, ray, static_cast<float>(noise_3sigma_m), j);
    if (noise_3sigma_m > options.end_distance_m) {
      // Noise beyond Eq. 1's final distance: it moves a point along its ray
      // by up to about 3 sigma, so pair along the ray. Nearer, the nearest
      // point is as good.
      thresholds.ray = ray;
      thresholds.max_along_ray_m = std::max(max_distance_m, noise_3sigma_m);
      j = FollowRayToSurface(model, p, thresholds.ray, static_cast<float>(noise_3sigma_m), j);
    } else {
      thresholds.ray.setZero();
    }
    const Eigen::Vector3f& q = model.points_o[j];
    const Eigen::Vector3f& n = model.normals_o[j];
    // A point whose colour is not known is paired on geometry (its colour: the scene's own).
    const Eigen::Vector3f& rgb_q = model.color_known(j) ? model.colors[j] : scene.colors[i];
    switch (ClassifyPair(p, oRc * scene.normals_c[i], scene.colors[i], q, n, rgb_q, thresholds)) {
      case Rejection::kNone:
        break;
      case Rejection::kNoModelPoint:
        ++stats.no_model;
        continue;
      case Rejection::kDistance:
        ++stats.distance;
        continue;
      case Rejection::kNormal:
        ++stats.normal;
        continue;
      case Rejection::kColor:
        ++stats.color;
        continue;
    }
    ++stats.inliers;
    const double r = (p - q).dot(n);
    stats.sum_r2 += r * r;
    if (!H) stats.normal_scatter += (n * n.transpose()).cast<double>();
    if (H) {
      Eigen::Matrix<double, 6, 1> J;
      J.head<3>() = p.cross(n).cast<double>();
      J.tail<3>() = n.cast<double>();
      H->selfadjointView<Eigen::Upper>().rankUpdate(J);
      *g += J * r;
      if (options.point_to_point_weight > 0.0) {
        const Eigen::Vector3d pd = p.cast<double>(), e = (p - q).cast<double>();
        stats.sum_p += pd;
        stats.sum_ppT.noalias() += pd * pd.transpose();
        stats.sum_p2 += pd.squaredNorm();
        stats.sum_p_cross_e += pd.cross(e);
        stats.sum_e += e;
      }
    }
  }
  if (H && options.point_to_point_weight > 0.0 && stats.inliers > 0) {
    // The point-to-point term pins sliding along flat faces: d(p + w x p + v - q)
    // = [-[p]x, I] [w; v], so it adds w * sum [-[p]x, I]^T [-[p]x, I] to H and
    // w * sum [p x e; e] to g; with [p]x^T [p]x = |p|^2 I - p p^T.
    const double w = options.point_to_point_weight;
    Eigen::Matrix<double, 6, 6> Hp;
    Hp.topLeftCorner<3, 3>() = stats.sum_p2 * Eigen::Matrix3d::Identity() - stats.sum_ppT;
    Hp.topRightCorner<3, 3>() = Skew(stats.sum_p);
    Hp.bottomLeftCorner<3, 3>() = -Skew(stats.sum_p);
    Hp.bottomRightCorner<3, 3>() = stats.inliers * Eigen::Matrix3d::Identity();
    H->noalias() += w * Hp;
    g->head<3>() += w * stats.sum_p_cross_e;
    g->tail<3>() += w * stats.sum_e;
  }
  return stats;
}

}  // namespace

std::size_t IcpWorkBound(std::size_t scene_points, const IcpOptions& options) {
  return scene_points * static_cast<std::size_t>(std::max(1, options.max_iterations) + 1);
}

IcpResult RefinePoseIcp(const ModelCloud& model, const SceneCloud& scene,
                        const Eigen::Isometry3d& cMo_init, const IcpOptions& options) {
  IcpResult result;
  result.cMo = cMo_init;
  result.scene_points = static_cast<int>(scene.points_c.size());
  if (scene.empty() || model.points_o.empty() || !cMo_init.matrix().allFinite()) return result;

  Eigen::Isometry3d oMc = cMo_init.inverse();
  const int n_it = std::max(1, options.max_iterations);
  double distance_m = options.start_distance_m;
  const double shrink =
      n_it > 1 ? std::pow(options.end_distance_m / options.start_distance_m, 1.0 / (n_it - 1))
               : 1.0;
  for (int it = 0; it < n_it; ++it, distance_m *= shrink) {
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    const PassStats stats = Associate(model, scene, oMc.cast<float>(), distance_m, options, &H, &g);
    result.iterations = it + 1;
    if (stats.inliers < options.min_inliers) return result;
    H.triangularView<Eigen::Lower>() = H.transpose();
    H.diagonal().array() += options.damping * H.trace() / 6.0;
    const Eigen::Matrix<double, 6, 1> delta = -H.ldlt().solve(g);
    if (!delta.allFinite()) return result;
    // oMc <- Exp(delta) * oMc (delta = rotation, translation in o).
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    const double angle = delta.head<3>().norm();
    if (angle > 1e-12)
      step.linear() = Eigen::AngleAxisd(angle, delta.head<3>() / angle).toRotationMatrix();
    step.translation() = delta.tail<3>();
    oMc = step * oMc;
    if (delta.tail<3>().norm() + 0.1 * angle < options.converged_step_m &&
        distance_m <= options.end_distance_m * 1.5)
      break;
  }
  oMc.linear() = Eigen::Quaterniond(oMc.linear()).normalized().toRotationMatrix();
  const PassStats final_stats =
      Associate(model, scene, oMc.cast<float>(), options.end_distance_m, options, nullptr, nullptr);
  result.inliers = final_stats.inliers;
  result.rejected_no_model = final_stats.no_model;
  result.rejected_distance = final_stats.distance;
  result.rejected_normal = final_stats.normal;
  result.rejected_color = final_stats.color;
  result.inlier_ratio = double(final_stats.inliers) / std::max(1, result.scene_points);
  result.rmse_m =
      final_stats.inliers > 0 ? std::sqrt(final_stats.sum_r2 / final_stats.inliers) : 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(final_stats.normal_scatter);
  if (eig.info() == Eigen::Success && eig.eigenvalues()[2] > 0.0) {
    result.weak_direction_o = eig.eigenvectors().col(0);
    result.weak_ratio = std::max(0.0, eig.eigenvalues()[0]) / eig.eigenvalues()[2];
  }
  result.cMo = oMc.inverse();
  result.ok = final_stats.inliers >= options.min_inliers && result.cMo.matrix().allFinite();
  return result;
}

}  // namespace aerograsp
