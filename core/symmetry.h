// The rotational symmetries of an object's mesh: the proper rotations that map
// its surface (and its vertex colours, when it has them) onto itself.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace aerograsp {

/// The rotations that map the object onto itself, about `center_o`: the map
/// p -> center_o + R (p - center_o) for each R. In a frame whose origin is the
/// centre (the shipped objects') that is oRo' itself.
struct ObjectSymmetry {
  /// Discrete symmetries oRo' (the identity first); a group, closed under
  /// composition. With a continuous axis: the rotations that the spin about
  /// the axis does not already give (the identity and a half turn across it).
  std::vector<Eigen::Matrix3d> rotations;
  /// Unit axis in o about which any rotation is a symmetry (a cylinder), if any.
  std::optional<Eigen::Vector3d> continuous_axis_o;
  /// The point the rotations fix, m in o (the area centroid of the surface).
  Eigen::Vector3d center_o = Eigen::Vector3d::Zero();
};

struct SymmetryOptions {
  /// A rotated surface point is on the surface when within this fraction of
  /// the bounding-box diagonal of it, (0, 0.05].
  double tolerance_ratio = 0.002;
  /// Points sampled on the surface (area-weighted) besides the vertices, [100, 100000].
  int surface_samples = 2000;
  /// At most this many vertices are tested (evenly spread), [0, 100000].
  int max_vertices = 3000;
  /// A candidate survives this fraction of points off the surface, [0, 0.2].
  double max_outlier_fraction = 0.005;
  /// Largest order n of a rotation 2 pi / n about a principal axis tried, [2, 1000].
  int max_axis_order = 64;
  std::uint64_t seed = 1;  ///< surface sampling seed

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// The full group of proper rotations mapping the mesh onto itself. Candidates
/// come from the principal axes of the surface's second moment (turns 2 pi / n
/// about each, any turn for a continuous axis) and from the vertices farthest
/// from the centroid (the rotations taking one pair of them onto another pair
/// at the same distances); each is kept when the rotated surface samples and
/// vertices lie on the surface within the tolerance with matching normals (and
/// colours), then the set is closed under composition.
/// @throws std::invalid_argument for a mesh without area or bad options.
ObjectSymmetry FindMeshSymmetries(const TriangleMesh& mesh, const SymmetryOptions& options = {});

/// xMo with its rotation replaced by xRo, a symmetric equivalent of xMo's
/// (e.g. ClosestSymmetricRotation's): the object's centre stays where xMo puts
/// it, so the pose shows the same object in the same place whatever o's origin.
Eigen::Isometry3d WithSymmetricRotation(const Eigen::Isometry3d& xMo, const Eigen::Matrix3d& xRo,
                                        const ObjectSymmetry& symmetry);

/// "24 rotations (a cube's group)", "continuous about (1, 0, 0) and a half turn
/// across it", "none (the identity only)".
std::string DescribeSymmetry(const ObjectSymmetry& symmetry);

}  // namespace aerograsp
