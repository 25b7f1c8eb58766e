// Synthetic scenes for the detection tests: the crawler's model cloud seen
// from a camera (front-facing points only), without a renderer.
#pragma once

#include <Eigen/Geometry>

#include "core/object_model.h"
#include "detection/model_cloud.h"
#include "detection/scene_cloud.h"

namespace aerograsp::testing {

/// The crawler's model cloud, built once per test binary.
inline const ModelCloud& CrawlerModel() {
  static const ModelCloud model = BuildModelCloud(ObjectModel::Load("crawler").mesh_o);
  return model;
}

/// The crawler's mesh without its vertex colours (a plain CAD mesh), as a model cloud.
inline const ModelCloud& PlainCrawlerModel() {
  static const ModelCloud model = [] {
    TriangleMesh mesh = ObjectModel::Load("crawler").mesh_o;
    mesh.colors.clear();
    return BuildModelCloud(mesh);
  }();
  return model;
}

/// The crawler's length: the axis of o its model cloud is longest along, half
/// that length, and the middle along the axis.
struct ModelLength {
  Eigen::Vector3d axis_o = Eigen::Vector3d::UnitX();
  double half_m = 0.0;
  double middle_m = 0.0;
};
inline ModelLength CrawlerLength() {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo;
  for (const Eigen::Vector3f& p : CrawlerModel().points_o) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Eigen::Index axis = 0;
  (hi - lo).maxCoeff(&axis);
  return {Eigen::Vector3d::Unit(axis), 0.5 * (hi - lo)[axis], 0.5 * (hi + lo)[axis]};
}

/// A typical view: the crawler 0.7 m ahead, seen from above and the side.
inline Eigen::Isometry3d TypicalCMo() {
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  cMo.linear() = (Eigen::AngleAxisd(2.3, Eigen::Vector3d::UnitX()) *
                  Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()))
                     .toRotationMatrix();
  cMo.translation() = Eigen::Vector3d(0.02, -0.01, 0.7);
  return cMo;
}

/// Every `stride`-th model point that faces the camera at cMo, in frame c,
/// with its normal and colour.
inline SceneCloud VisibleScene(const ModelCloud& model, const Eigen::Isometry3d& cMo,
                               int stride = 3) {
  SceneCloud scene;
  const Eigen::Isometry3f T = cMo.cast<float>();
  for (std::size_t i = 0; i < model.points_o.size(); i += stride) {
    const Eigen::Vector3f p = T * model.points_o[i];
    const Eigen::Vector3f n = T.linear() * model.normals_o[i];
    if (n.dot(p) >= -0.1f * p.norm()) continue;
    scene.points_c.push_back(p);
    scene.normals_c.push_back(n);
    scene.colors.push_back(model.has_colors() ? model.colors[i] : Eigen::Vector3f(128, 128, 128));
  }
  scene.valid_pixels = static_cast<int>(scene.points_c.size());
  return scene;
}

inline Eigen::Isometry3d Perturbed(const Eigen::Isometry3d& cMo, const Eigen::Vector3d& dt_m,
                                   const Eigen::Vector3d& rotvec_rad) {
  Eigen::Isometry3d out = cMo;
  out.translation() += dt_m;
  out.linear() = Eigen::AngleAxisd(rotvec_rad.norm(), rotvec_rad.normalized()).toRotationMatrix() *
                 cMo.linear();
  return out;
}

}  // namespace aerograsp::testing
