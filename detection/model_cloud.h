// The object model as the pose pipeline uses it: points sampled on the mesh
// surface in frame o, each with its outward normal and, when the mesh has
// vertex colours, its colour (a plain mesh has none: nothing compares colour
// against it, docs/perception.md), plus a voxel
// grid that answers "nearest model point" in O(1) for ICP, and the object's
// rotational symmetries (for the EKF and for rotation errors).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/mesh.h"
#include "core/symmetry.h"

namespace aerograsp {

struct ModelCloud {
  std::vector<Eigen::Vector3f> points_o;   ///< m, frame o
  std::vector<Eigen::Vector3f> normals_o;  ///< unit, outward
  /// RGB 0..255, one per point; empty when the mesh has no vertex colours.
  std::vector<Eigen::Vector3f> colors;
  double diameter_m = 0.0;  ///< largest distance between two points (ADD-S threshold base)
  /// Centre of the mesh's bounding box (frame o, m) and the distance from it to
  /// the box's corners: where to place the object around an estimated centre,
  /// and how far from that centre a scene point can still be on it.
  Eigen::Vector3d box_center_o = Eigen::Vector3d::Zero();
  double box_radius_m = 0.0;
  ObjectSymmetry symmetry;

  /// Whether the points carry the mesh's colours: the colour checks (ICP's
  /// Eq. 3, the pose support's) apply only then.
  bool has_colors() const { return !colors.empty(); }
  /// The colour a point has where the object does not look like its mesh (a
  /// label or a tag board fixed on it, ForgetColorsInBox): nothing compares it.
  static constexpr float kUnknownColor = -1.0f;
  /// Whether point i's colour describes the object (has_colors() and not forgotten).
  bool color_known(std::size_t i) const { return has_colors() && colors[i].x() >= 0.0f; }

  /// Nearest-point grid over the model's bounds grown by `margin_m`: cells of
  /// `cell_m`, each holding the index of the model point nearest its centre, or
  /// -1 when none is within margin_m.
  Eigen::Vector3f grid_min_o = Eigen::Vector3f::Zero();
  float cell_m = 0.004f;
  float margin_m = 0.0f;
  Eigen::Vector3i grid_size = Eigen::Vector3i::Zero();
  std::vector<std::int32_t> grid;

  /// Index of the model point nearest p_o (approximately: exact for the cell
  /// centre), or -1 outside the grid or beyond the margin.
  int Nearest(const Eigen::Vector3f& p_o) const {
    const Eigen::Vector3f g = (p_o - grid_min_o) / cell_m;
    const int x = static_cast<int>(g.x()), y = static_cast<int>(g.y()), z = static_cast<int>(g.z());
    if (g.x() < 0 || g.y() < 0 || g.z() < 0 || x >= grid_size.x() || y >= grid_size.y() ||
        z >= grid_size.z()) {
      return -1;
    }
    return grid[(static_cast<std::size_t>(z) * grid_size.y() + y) * grid_size.x() + x];
  }
};

struct ModelCloudOptions {
  double spacing_m = 0.004;  ///< mean distance between surface samples, [0.001, 0.05] m
  double cell_m = 0.003;     ///< nearest-point grid cell, [0.001, 0.05] m
  /// grid reaches this far from the surface (>= ICP's largest distance), m
  double margin_m = 0.05;
  std::uint64_t seed = 1;  ///< surface sampling seed
};

/// Samples the mesh (area-weighted, colours interpolated like the renderer when
/// the mesh has one per vertex; none otherwise),
/// builds the grid and finds the symmetries (FindMeshSymmetries).
/// @throws std::invalid_argument for a mesh with no area or options out of range.
ModelCloud BuildModelCloud(const TriangleMesh& mesh_o, const ModelCloudOptions& options = {});

/// Forgets the colours of the model points inside the box bMo (the box's frame
/// b from o; half extents m along b's axes): something of unknown appearance
/// covers the object there (a printed tag board, a label), so the colour checks
/// pass those points on geometry alone. Nothing for a model without colours.
void ForgetColorsInBox(ModelCloud* model, const Eigen::Isometry3d& oMb,
                       const Eigen::Vector3d& half_extents_m);

/// Rotation error (rad) between an estimate and the truth of cRo, taken over
/// the symmetries: min over S of angle(R_true^-1 * R_est * S); with a
/// continuous axis a, the angle between the axes R_est*a and R_true*a (after
/// the discrete flips), i.e. the spin about the axis does not count.
double SymmetricRotationError(const Eigen::Matrix3d& cRo_est, const Eigen::Matrix3d& cRo_true,
                              const ObjectSymmetry& symmetry);

/// The symmetric equivalent of cRo_meas closest to cRo_ref: cRo_meas * S for
/// the best discrete S, then spun about the continuous axis (if any) to match.
Eigen::Matrix3d ClosestSymmetricRotation(const Eigen::Matrix3d& cRo_meas,
                                         const Eigen::Matrix3d& cRo_ref,
                                         const ObjectSymmetry& symmetry);

}  // namespace aerograsp
