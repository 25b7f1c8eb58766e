#include "detection/global_registration.h"

#include <pcl/features/fpfh_omp.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/sample_consensus_prerejective.h>
#include <pcl/search/kdtree.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <thread>
#include <unordered_set>

#include "core/conversions.h"
#include "core/parallel.h"
#include "core/random.h"

namespace aerograsp {
namespace {

using PointT = pcl::PointNormal;
using Cloud = pcl::PointCloud<PointT>;
using Features = pcl::PointCloud<pcl::FPFHSignature33>;

/// One point per occupied voxel (the first seen), skipping zero normals.
Cloud::Ptr Downsample(const std::vector<Eigen::Vector3f>& points,
                      const std::vector<Eigen::Vector3f>& normals, double voxel_m) {
  Cloud::Ptr cloud(new Cloud);
  std::unordered_set<std::int64_t> seen;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (normals[i].isZero()) continue;
    const Eigen::Vector3i key = (points[i] / voxel_m).array().floor().cast<int>();
    const std::int64_t hash = (std::int64_t(key.x()) * 73856093) ^
                              (std::int64_t(key.y()) * 19349663) ^
                              (std::int64_t(key.z()) * 83492791);
    if (!seen.insert(hash).second) continue;
    PointT p;
    p.getVector3fMap() = points[i];
    p.getNormalVector3fMap() = normals[i];
    cloud->push_back(p);
  }
  return cloud;
}

Cloud::Ptr ToCloud(const std::vector<Eigen::Vector3f>& points,
                   const std::vector<Eigen::Vector3f>& normals) {
  Cloud::Ptr cloud(new Cloud);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (normals[i].isZero()) continue;
    PointT p;
    p.getVector3fMap() = points[i];
    p.getNormalVector3fMap() = normals[i];
    cloud->push_back(p);
  }
  return cloud;
}

/// FPFH of the keypoints over the surface, on all cores (each point's
/// histogram is computed alone: the same values as on one).
Features::Ptr ComputeFpfh(const Cloud::Ptr& keypoints, const Cloud::Ptr& surface, double radius_m) {
  pcl::FPFHEstimationOMP<PointT, PointT, pcl::FPFHSignature33> fpfh(
      std::max(1u, std::thread::hardware_concurrency()));
  fpfh.setInputCloud(keypoints);
  fpfh.setSearchSurface(surface);
  fpfh.setInputNormals(surface);
  fpfh.setSearchMethod(pcl::search::KdTree<PointT>::Ptr(new pcl::search::KdTree<PointT>));
  fpfh.setRadiusSearch(radius_m);
  Features::Ptr features(new Features);
  fpfh.compute(*features);
  return features;
}

}  // namespace

struct GlobalRegistration::Impl {
  const ModelCloud* model;
  GlobalRegistrationOptions options;
  Cloud::Ptr model_keypoints;
  Features::Ptr model_features;
  std::vector<Eigen::Matrix3d> orientations;  // fixed, uniformly random cRo hypotheses
};

GlobalRegistration::GlobalRegistration(const ModelCloud& model,
                                       const GlobalRegistrationOptions& options)
    : impl_(new Impl) {
  impl_->model = &model;
  impl_->options = options;
  impl_->model_keypoints = Downsample(model.points_o, model.normals_o, options.voxel_m);
  if (options.attempts > 0) {
    impl_->model_features = ComputeFpfh(
        impl_->model_keypoints, ToCloud(model.points_o, model.normals_o), options.feature_radius_m);
  }
  FastRandom rng(options.seed);
  for (int i = 0; i < options.orientations; ++i) {
    impl_->orientations.push_back(
        Eigen::Quaterniond(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal())
            .normalized()
            .toRotationMatrix());
  }
}

GlobalRegistration::~GlobalRegistration() = default;

std::size_t GlobalRegistration::HypothesisCount(const SceneCloud& scene, std::size_t centres,
                                                bool every_orientation) const {
  const std::size_t all = impl_->orientations.size();
  if (scene.points_c.size() < 30 || all == 0) return 0;
  return centres == 1 || every_orientation ? centres * all
                                           : centres * std::max<std::size_t>(1, all / 4);
}

SceneCloud GlobalRegistration::Near(const SceneCloud& scene, const Eigen::Vector3d& centre_c,
                                    double reach_m, std::size_t stride) {
  SceneCloud near;
  const Eigen::Vector3f centre = centre_c.cast<float>();
  const float reach2 = static_cast<float>(reach_m * reach_m);
  for (std::size_t i = 0; i < scene.points_c.size(); i += std::max<std::size_t>(1, stride)) {
    if ((scene.points_c[i] - centre).squaredNorm() > reach2) continue;
    near.points_c.push_back(scene.points_c[i]);
    near.normals_c.push_back(scene.normals_c[i]);
    near.colors.push_back(scene.colors[i]);
  }
  near.valid_pixels = static_cast<int>(near.points_c.size());
  return near;
}

IcpOptions GlobalRegistration::QuickIcp(const IcpOptions& icp) {
  IcpOptions quick = icp;
  quick.max_iterations = 6;
  quick.start_distance_m = std::max(icp.start_distance_m, 0.04);
  quick.end_distance_m = std::max(icp.end_distance_m, 0.01);
  quick.min_inliers = 10;
  return quick;
}

std::vector<IcpResult> GlobalRegistration::Hypotheses(
    const SceneCloud& scene, const IcpOptions& icp, const std::vector<Eigen::Vector3d>& centres_c,
    std::size_t first, WorkBudget* budget, std::int64_t extra_work, bool every_orientation) const {
  const ModelCloud& model = *impl_->model;
  const std::size_t total =
      centres_c.empty() ? 0 : HypothesisCount(scene, centres_c.size(), every_orientation);
  if (first >= total) return {};
  const IcpOptions quick = QuickIcp(icp);
  const std::size_t per_centre = total / centres_c.size();
  // Each centre's cloud: a quarter of the scene's points, those within the
  // object's reach of the centre (a point farther than that pairs with nothing).
  const double reach_m = model.box_radius_m + quick.start_distance_m;
  std::vector<SceneCloud> near(centres_c.size());
  std::vector<bool> built(centres_c.size(), false);
  std::size_t end = first;
  for (std::size_t h = first; h < total; ++h) {
    const std::size_t c = h / per_centre;
    if (!built[c]) {
      if (!budget->Take(static_cast<std::int64_t>(scene.points_c.size()))) break;
      near[c] = Near(scene, centres_c[c], reach_m, 4);
      built[c] = true;
    }
    if (!budget->Take(static_cast<std::int64_t>(IcpWorkBound(near[c].points_c.size(), quick)) +
                      extra_work))
      break;
    end = h + 1;
  }
  // Each ICP alone, kept in this order whatever thread ran it.
  std::vector<IcpResult> tried(end - first);
  ParallelFor(tried.size(), [&](std::size_t k) {
    const std::size_t h = first + k;
    Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
    cMo.linear() = impl_->orientations[h % per_centre];
    cMo.translation() = centres_c[h / per_centre] - cMo.linear() * model.box_center_o;
    tried[k] = RefinePoseIcp(model, near[h / per_centre], cMo, quick);
  });
  return tried;
}

std::vector<IcpResult> GlobalRegistration::Best(std::vector<IcpResult> hypotheses,
                                                const std::vector<double>& scores) const {
  std::vector<IcpResult> best;
  if (!scores.empty() && scores.size() == hypotheses.size()) {
    // By score (ties: the earlier hypothesis first).
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < hypotheses.size(); ++i) {
      if (hypotheses[i].ok) order.push_back(i);
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
    for (std::size_t i : order) best.push_back(std::move(hypotheses[i]));
  } else {
    for (IcpResult& r : hypotheses) {
      if (r.ok) best.push_back(std::move(r));
    }
    std::sort(best.begin(), best.end(),
              [](const IcpResult& a, const IcpResult& b) { return a.inliers > b.inliers; });
  }
  best.resize(std::min<std::size_t>(best.size(), std::max(0, impl_->options.refined_orientations)));
  return best;
}

std::vector<IcpResult> GlobalRegistration::FeatureCandidates(const SceneCloud& scene,
                                                             const IcpOptions& icp) const {
  std::vector<IcpResult> out;
  const GlobalRegistrationOptions& options = impl_->options;
  if (options.attempts <= 0) return out;
  Cloud::Ptr surface = ToCloud(scene.points_c, scene.normals_c);
  Cloud::Ptr keypoints = Downsample(scene.points_c, scene.normals_c, options.voxel_m);
  if (keypoints->size() < 10 || impl_->model_keypoints->size() < 10) return out;
  Features::Ptr features = ComputeFpfh(keypoints, surface, options.feature_radius_m);
  // Features of points with too few neighbours are NaN: drop them.
  Cloud::Ptr source(new Cloud);
  Features::Ptr source_features(new Features);
  for (std::size_t i = 0; i < keypoints->size(); ++i) {
    if (std::isfinite(features->points[i].histogram[0])) {
      source->push_back(keypoints->points[i]);
      source_features->push_back(features->points[i]);
    }
  }
  if (source->size() < 10) return out;
  for (int attempt = 0; attempt < options.attempts; ++attempt) {
    pcl::SampleConsensusPrerejective<PointT, PointT, pcl::FPFHSignature33> ransac;
    ransac.setInputSource(source);
    ransac.setSourceFeatures(source_features);
    ransac.setInputTarget(impl_->model_keypoints);
    ransac.setTargetFeatures(impl_->model_features);
    ransac.setMaximumIterations(options.max_iterations);
    ransac.setNumberOfSamples(3);
    ransac.setCorrespondenceRandomness(4);
    ransac.setSimilarityThreshold(0.85f);
    ransac.setMaxCorrespondenceDistance(2.0 * options.voxel_m);
    ransac.setInlierFraction(static_cast<float>(options.inlier_fraction));
    std::srand(static_cast<unsigned>(options.seed + attempt));  // PCL's sampling uses rand()
    Cloud aligned;
    ransac.align(aligned);
    if (!ransac.hasConverged()) continue;
    const Eigen::Isometry3d oMc = FromPclMatrix(ransac.getFinalTransformation());
    IcpResult refined = RefinePoseIcp(*impl_->model, scene, oMc.inverse(), icp);
    if (refined.ok) out.push_back(refined);
  }
  return out;
}

}  // namespace aerograsp
