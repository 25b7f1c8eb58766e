// Collision checks of the platform with FCL: each arm against the safe volume,
// the two arms against each other, and an arm against an object's triangle mesh.
// Everything is expressed in the drone body frame d (FRD, core/frames.h); units
// are metres and radians. FCL stays in collision.cpp (pimpl).
#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "core/mesh.h"
#include "core/platform.h"

namespace aerograsp {

/// Collision queries on one platform. The collision geometry is built once by
/// the constructor (description); a query only computes the segment poses for
/// the joint positions it is given and runs FCL on the pre-built shapes, so the
/// const queries keep no state and may run concurrently. AddMesh is the only
/// mutating call and must not run concurrently with queries.
///
/// Shapes: the URDF boxes, cylinders and spheres of the arm segments and of the
/// safe volume, exactly as written (not inflated: a clearance is the `margin_m`
/// argument of each query). URDF mesh shapes are skipped: the shipped arms and
/// vehicle describe every part with primitives.
///
/// Each query first compares axis-aligned bounding boxes in d and only calls
/// FCL for the pairs whose boxes are within the margin; with the arms away from
/// the volume a safe-volume query is about a microsecond.
class PlatformCollision {
 public:
  /// Whether the fingers take part in ArmHitsMesh.
  enum class Fingers { kInclude, kExclude };

  /// Builds the FCL shapes of both arms and of the safe volume; copies what it
  /// needs, so `platform` may be destroyed afterwards.
  /// @throws std::invalid_argument naming the config when the safe volume has no
  /// box, cylinder or sphere (every query against it would pass vacuously).
  explicit PlatformCollision(const Platform& platform);
  ~PlatformCollision();
  PlatformCollision(const PlatformCollision&) = delete;
  PlatformCollision& operator=(const PlatformCollision&) = delete;
  PlatformCollision(PlatformCollision&&) noexcept;
  PlatformCollision& operator=(PlatformCollision&&) noexcept;

  /// Number of leading segments of the arm (segments 0 .. n-1) exempt from the
  /// safe-volume test: the segments that can only turn about the line from the
  /// arm base through their joints, so their place never changes. Rule: with k
  /// the index of the first joint that is prismatic or whose axis is not
  /// collinear with the line from the base origin to the joint origin (the
  /// shoulder pitch, at ArmModel::ShoulderPosition()), segments 0..k are exempt
  /// and n = k + 1. For the shipped arms n = 2: the base plate with the shoulder
  /// top (segment 0) and the yawing shoulder (segment 1) sit inside or on the
  /// volume by design. Segments from k + 1 on move with the shoulder pitch and
  /// are checked.
  int ExemptSegmentCount(Side side) const;

  /// True when any non-exempt segment of the arm at joint positions q (rad,
  /// size dof()) is within margin_m (m, >= 0) of the safe volume; penetration
  /// counts. With margin_m = 0 only touching or penetration counts.
  /// A q with a NaN or infinite entry returns true (unknown counts as unsafe).
  /// @throws std::invalid_argument when q has the wrong size or margin_m is
  /// negative or not finite.
  bool ArmInSafeVolume(Side side, const Eigen::VectorXd& q, double margin_m = 0.0) const;

  /// Smallest signed distance (m) between the arm's non-exempt segments at q
  /// (rad) and the safe volume: positive when apart, zero when touching, minus
  /// the deepest penetration depth when they overlap (exact for two boxes; by
  /// FCL's EPA, or its cruder MPR where EPA fails, for cylinders and spheres).
  /// About 3 us apart; tens of us when several shapes penetrate.
  /// ArmInSafeVolume(side, q, m) is DistanceToSafeVolume(side, q) < m for m > 0.
  /// A q with a NaN or infinite entry returns -infinity, so a threshold check
  /// stops.
  /// @throws std::invalid_argument when q has the wrong size.
  double DistanceToSafeVolume(Side side, const Eigen::VectorXd& q) const;

  /// True when any segment of the left arm at q_left (rad) is within margin_m
  /// (m, >= 0) of any segment of the right arm at q_right. Pairs of two exempt
  /// segments (the shoulders, 0.305 m apart and fixed in place) are not tested;
  /// an exempt segment of one arm is tested against every moving segment of the
  /// other. A q with a NaN or infinite entry returns true.
  /// @throws std::invalid_argument when a q has the wrong size or margin_m is
  /// negative or not finite.
  bool ArmsCollide(const Eigen::VectorXd& q_left, const Eigen::VectorXd& q_right,
                   double margin_m = 0.0) const;

  /// Builds the bounding volume hierarchy of an object's mesh once, with its
  /// vertices in the object frame o (m), and returns the handle ArmHitsMesh
  /// takes (0, 1, 2, ... in the order of the calls). A closed mesh
  /// (CheckMesh(mesh_o).IsClosed()) is treated as a solid, any other mesh as a
  /// surface: see ArmHitsMesh.
  /// @throws std::invalid_argument when the mesh has no triangles, an index out
  /// of range or a non-finite vertex.
  int AddMesh(const TriangleMesh& mesh_o);

  /// True when a segment of the arm at q (rad) is within margin_m (m, >= 0) of
  /// the mesh `handle` placed at dMo (the object frame o in the body frame d).
  /// Every segment takes part, the base included. Fingers::kExclude leaves out
  /// the fingers: the shapes of the tool's segment that lie entirely on one side
  /// of the approach axis (their extent along the closing axis x_e excludes 0),
  /// for a grasp whose fingers are meant to close on the object; the gripper
  /// housing, which straddles the axis, is always tested.
  /// For a closed mesh a shape entirely inside the object also counts (tested
  /// by ray parity from the shape's centre, linear in the triangles, only for
  /// the shapes inside the object's bounding box that touch no triangle); for
  /// an open mesh only the distance to its triangles counts.
  /// A q with a NaN or infinite entry, or a non-finite dMo, returns true.
  /// @throws std::out_of_range for a handle AddMesh did not return;
  /// std::invalid_argument when q has the wrong size or margin_m is negative or
  /// not finite.
  bool ArmHitsMesh(Side side, const Eigen::VectorXd& q, int handle, const Eigen::Isometry3d& dMo,
                   double margin_m = 0.0, Fingers fingers = Fingers::kInclude) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aerograsp
