#include "detection/model_cloud.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/random.h"
#include "core/transforms.h"

namespace aerograsp {

ModelCloud BuildModelCloud(const TriangleMesh& mesh_o, const ModelCloudOptions& options) {
  if (!(options.spacing_m >= 0.001 && options.spacing_m <= 0.05) ||
      !(options.cell_m >= 0.001 && options.cell_m <= 0.05) ||
      !(options.margin_m > 0.0 && options.margin_m <= 0.5)) {
    throw std::invalid_argument("BuildModelCloud: spacing_m, cell_m or margin_m out of range");
  }
  const std::size_t nt = mesh_o.triangles.size();
  std::vector<double> cumulative_area(nt, 0.0);
  double area = 0.0;
  for (std::size_t i = 0; i < nt; ++i) {
    const Eigen::Vector3i& t = mesh_o.triangles[i];
    area += 0.5 * (mesh_o.vertices[t[1]] - mesh_o.vertices[t[0]])
                      .cross(mesh_o.vertices[t[2]] - mesh_o.vertices[t[0]])
                      .norm();
    cumulative_area[i] = area;
  }
  if (!(area > 0.0)) throw std::invalid_argument("BuildModelCloud: the mesh has no area");
  const std::size_t count = std::min<std::size_t>(
      200000, static_cast<std::size_t>(area / (options.spacing_m * options.spacing_m)) + 1);

  ModelCloud model;
  FastRandom rng(options.seed);
  const bool has_colors = mesh_o.colors.size() == mesh_o.vertices.size();
  for (std::size_t k = 0; k < count; ++k) {
    const double pick = rng.Uniform(0.0, area);
    const std::size_t i = std::min<std::size_t>(
        nt - 1, std::lower_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
                    cumulative_area.begin());
    const Eigen::Vector3d normal = mesh_o.TriangleNormal(i);
    if (normal.isZero()) continue;
    double a = rng.Uniform(), b = rng.Uniform();
    if (a + b > 1.0) {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    const Eigen::Vector3i& t = mesh_o.triangles[i];
    const Eigen::Vector3d p = (1.0 - a - b) * mesh_o.vertices[t[0]] + a * mesh_o.vertices[t[1]] +
                              b * mesh_o.vertices[t[2]];
    model.points_o.push_back(p.cast<float>());
    model.normals_o.push_back(normal.cast<float>());
    if (has_colors) {
      Eigen::Vector3f color = Eigen::Vector3f::Zero();
      const double w[3] = {1.0 - a - b, a, b};
      for (int c = 0; c < 3; ++c) {
        for (int v = 0; v < 3; ++v) color[c] += static_cast<float>(w[v] * mesh_o.colors[t[v]][c]);
      }
      model.colors.push_back(color);
    }
  }

  // Diameter from a subsample (exact enough for a 10 % threshold).
  const std::size_t n = model.points_o.size();
  const std::size_t step = std::max<std::size_t>(1, n / 1500);
  float d2 = 0.0f;
  for (std::size_t i = 0; i < n; i += step) {
    for (std::size_t j = i + step; j < n; j += step)
      d2 = std::max(d2, (model.points_o[i] - model.points_o[j]).squaredNorm());
  }
  model.diameter_m = std::sqrt(d2);
  model.box_center_o = 0.5 * (mesh_o.BoundsMin() + mesh_o.BoundsMax());
  model.box_radius_m = 0.5 * (mesh_o.BoundsMax() - mesh_o.BoundsMin()).norm();

  // Nearest-point grid.
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(n);
  Eigen::Vector3f lo = model.points_o[0], hi = model.points_o[0];
  for (const Eigen::Vector3f& p : model.points_o) {
    cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  model.cell_m = static_cast<float>(options.cell_m);
  model.margin_m = static_cast<float>(options.margin_m);
  model.grid_min_o = lo - Eigen::Vector3f::Constant(model.margin_m);
  const Eigen::Vector3f extent = hi - lo + Eigen::Vector3f::Constant(2.0f * model.margin_m);
  model.grid_size = (extent / model.cell_m).array().ceil().cast<int>();
  model.grid.assign(static_cast<std::size_t>(model.grid_size.prod()), -1);
  std::vector<int> index(1);
  std::vector<float> dist2(1);
  const float margin2 = model.margin_m * model.margin_m;
  std::size_t cell = 0;
  for (int z = 0; z < model.grid_size.z(); ++z) {
    for (int y = 0; y < model.grid_size.y(); ++y) {
      for (int x = 0; x < model.grid_size.x(); ++x, ++cell) {
        const Eigen::Vector3f c =
            model.grid_min_o + model.cell_m * Eigen::Vector3f(x + 0.5f, y + 0.5f, z + 0.5f);
        if (tree.nearestKSearch(pcl::PointXYZ(c.x(), c.y(), c.z()), 1, index, dist2) == 1 &&
            dist2[0] <= margin2) {
          model.grid[cell] = index[0];
        }
      }
    }
  }
  model.symmetry = FindMeshSymmetries(mesh_o);
  return model;
}

void ForgetColorsInBox(ModelCloud* model, const Eigen::Isometry3d& oMb,
                       const Eigen::Vector3d& half_extents_m) {
  if (!model->has_colors()) return;
  const Eigen::Isometry3f bMo = oMb.inverse().cast<float>();
  const Eigen::Vector3f half = half_extents_m.cast<float>();
  for (std::size_t i = 0; i < model->points_o.size(); ++i) {
    const Eigen::Vector3f p_b = bMo * model->points_o[i];
    if ((p_b.cwiseAbs().array() <= half.array()).all())
      model->colors[i].setConstant(ModelCloud::kUnknownColor);
  }
}

namespace {

/// cRo * Rot(a, phi) with phi maximising trace(cRo_ref^T * cRo * Rot(a, phi)).
Eigen::Matrix3d SpinToMatch(const Eigen::Matrix3d& cRo, const Eigen::Matrix3d& cRo_ref,
                            const Eigen::Vector3d& a) {
  const Eigen::Matrix3d M = cRo_ref.transpose() * cRo;
  const double along = a.dot(M * a);
  const double c = M.trace() - along;
  const double s = (M * Skew(a)).trace();
  const double phi = std::atan2(s, c);
  return cRo * Eigen::AngleAxisd(phi, a).toRotationMatrix();
}

}  // namespace

double SymmetricRotationError(const Eigen::Matrix3d& cRo_est, const Eigen::Matrix3d& cRo_true,
                              const ObjectSymmetry& symmetry) {
  double best = M_PI;
  for (const Eigen::Matrix3d& S : symmetry.rotations) {
    const Eigen::Matrix3d R = cRo_est * S;
    double error;
    if (symmetry.continuous_axis_o) {
      const Eigen::Vector3d& a = *symmetry.continuous_axis_o;
      error = std::acos(std::clamp((R * a).dot(cRo_true * a), -1.0, 1.0));
    } else {
      error = RotationAngle(cRo_true.transpose() * R);
    }
    best = std::min(best, error);
  }
  return best;
}

Eigen::Matrix3d ClosestSymmetricRotation(const Eigen::Matrix3d& cRo_meas,
                                         const Eigen::Matrix3d& cRo_ref,
                                         const ObjectSymmetry& symmetry) {
  Eigen::Matrix3d best = cRo_meas;
  double best_angle = 10.0;
  for (const Eigen::Matrix3d& S : symmetry.rotations) {
    Eigen::Matrix3d R = cRo_meas * S;
    if (symmetry.continuous_axis_o) R = SpinToMatch(R, cRo_ref, *symmetry.continuous_axis_o);
    const double angle = RotationAngle(cRo_ref.transpose() * R);
    if (angle < best_angle) {
      best_angle = angle;
      best = R;
    }
  }
  return best;
}

}  // namespace aerograsp
