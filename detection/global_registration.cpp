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
  impl_->model_features = ComputeFpfh(
      impl_->model_keypoints, ToCloud(model.points_o, model.normals_o), options.feature_radius_m);
  FastRandom rng(options.seed);
  for (int i = 0; i < options.orientations; ++i) {
    impl_->orientations.push_back(
        Eigen::Quaterniond(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal())
            .normalized()
            .toRotationMatrix());
  }
}

GlobalRegistration::~GlobalRegistration() = default;

std::vector<IcpResult> GlobalRegistration::Candidates(
    const SceneCloud& scene, const IcpOptions& icp,
    const std::vector<Eigen::Vector3d>& centres_c) const {
  std::vector<IcpResult> out;
  const GlobalRegistrationOptions& options = impl_->options;
  if (!centres_c.empty() && !impl_->orientations.empty() && scene.points_c.size() >= 30) {
    // Coarse: a short ICP of every orientation on a quarter of the scene.
    SceneCloud coarse;
    for (std::size_t i = 0; i < scene.points_c.size(); i += 4) {
      coarse.points_c.push_back(scene.points_c[i]);
      coarse.normals_c.push_back(scene.normals_c[i]);
      coarse.colors.push_back(scene.colors[i]);
    }
    IcpOptions quick = icp;
    quick.max_iterations = 6;
    quick.start_distance_m = std::max(icp.start_distance_m, 0.04);
    quick.end_distance_m = std::max(icp.end_distance_m, 0.01);
    quick.min_inliers = 10;
    const std::size_t per_centre = centres_c.size() == 1
                                       ? impl_->orientations.size()
                                       : std::max<std::size_t>(1, impl_->orientations.size() / 4);
    // Hypothesis h: centre h / per_centre, orientation h % per_centre (each
    // ICP alone, kept in this order whatever thread ran it).
    std::vector<IcpResult> tried(centres_c.size() * per_centre);
    ParallelFor(tried.size(), [&](std::size_t h) {
      Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
      cMo.linear() = impl_->orientations[h % per_centre];
      cMo.translation() = centres_c[h / per_centre];
      tried[h] = RefinePoseIcp(*impl_->model, coarse, cMo, quick);
    });
    std::vector<IcpResult> coarse_results;
    for (const IcpResult& r : tried) {
      if (r.ok) coarse_results.push_back(r);
    }
    std::sort(coarse_results.begin(), coarse_results.end(),
              [](const IcpResult& a, const IcpResult& b) { return a.inliers > b.inliers; });
    coarse_results.resize(
        std::min<std::size_t>(coarse_results.size(), std::max(0, options.refined_orientations)));
    ParallelFor(coarse_results.size(), [&](std::size_t k) {
      coarse_results[k] = RefinePoseIcp(*impl_->model, scene, coarse_results[k].cMo, icp);
    });
    for (const IcpResult& refined : coarse_results) {
      if (refined.ok) out.push_back(refined);
    }
  }
  Cloud::Ptr surface = ToCloud(scene.points_c, scene.normals_c);
  Cloud::Ptr keypoints = Downsample(scene.points_c, scene.normals_c, options.voxel_m);
  auto best_first = [&out] {
    std::sort(out.begin(), out.end(),
              [](const IcpResult& a, const IcpResult& b) { return a.inliers > b.inliers; });
    return out;
  };
  if (keypoints->size() < 10 || impl_->model_keypoints->size() < 10) return best_first();
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
  if (source->size() < 10) return best_first();
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
  return best_first();
}

}  // namespace aerograsp
