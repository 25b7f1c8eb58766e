// Contact-point candidates of a two-finger grasp, by ray casting through the
// object's mesh (paper Sect. 4.1, Eq. 4). Everything is in the object frame o
// (the frame the mesh is written in), in metres. Embree stays in contacts.cpp.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/platform.h"

namespace aerograsp {

struct ContactOptions {
  double resolution_m{0.015};  ///< spacing of the ray grid, [0.001, 0.1] m (paper: 0.015)

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// A point on the object's surface with the mesh's outward unit normal there.
struct Contact {
  Eigen::Vector3d p_o = Eigen::Vector3d::Zero();  ///< m, object frame
  Eigen::Vector3d n_o = Eigen::Vector3d::Zero();  ///< outward unit normal, object frame
};

/// Two contacts the fingers can close on: `a` where a ray enters the object,
/// `b` where it leaves it (possibly several folds later), so the fingers
/// squeeze along b - a.
struct ContactPair {
  Contact a, b;
  int axis = 0;  ///< the o axis (0 x, 1 y, 2 z) the ray ran along

  double width_m() const { return (b.p_o - a.p_o).norm(); }
  /// Midpoint of the two contacts (where the tool point's axis passes).
  Eigen::Vector3d center_o() const { return 0.5 * (a.p_o + b.p_o); }
  /// Unit closing axis from a to b.
  Eigen::Vector3d closing_axis_o() const { return (b.p_o - a.p_o).normalized(); }
};

/// The untransformed contacts of one object (what the cache stores).
struct ContactSet {
  std::vector<ContactPair> pairs;
  double resolution_m = 0.0;
  int rays = 0;              ///< rays cast
  int rays_hit = 0;          ///< rays that crossed the object
  int rays_skipped = 0;      ///< rays dropped: grazing a face or hits not alternating in/out
  int pairs_too_wide = 0;    ///< entry/exit combinations wider than the gripper takes
  double max_width_m = 0.0;  ///< widest pair the gripper takes (aperture minus clearances)
};

/// Casts a grid of rays along each axis of o through the mesh's bounding box
/// (rays at the cell centres of a grid with spacing options.resolution_m on each
/// face; a ray from the opposite face is the same line and gives the same
/// contacts, so each line is cast once), keeps every hit along each ray, sorts
/// them, and pairs entry i with exit k >= i: a ray through F folds gives
/// sum_{j=1..F} j = F (F + 1) / 2 pairs (Eq. 4), so the inner nooks of a
/// non-convex object are offered. A pair is kept when its width is at most
/// gripper.max_aperture_m - 2 gripper.finger_clearance_m. Normals are the
/// mesh's triangle normals. Deterministic; one thread.
/// Precondition: a closed mesh (LoadClosedMesh).
/// @throws std::invalid_argument when the mesh has no triangles or the options
/// are invalid.
ContactSet ComputeContactPairs(const TriangleMesh& mesh_o, const GripperConfig& gripper,
                               const ContactOptions& options);

/// Whether the pair's contacts stay where they are with the object shifted by
/// margin_m either way along each of the two o axes across its ray (a pose
/// error along the faces the fingers close on): the ray along the pair's axis
/// through its centre so shifted still enters the object within 5 mm of `a`
/// and leaves it within 5 mm of `b` (along the axis). A pair within margin_m of
/// an edge of either face fails. Brute-force ray casts (core/mesh IntersectRay).
/// Precondition: a closed mesh. margin_m 0 is always true.
bool ContactsClearOfEdges(const TriangleMesh& mesh_o, const ContactPair& pair, double margin_m);

}  // namespace aerograsp
