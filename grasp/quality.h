// Grasp quality (paper Sect. 4.1, after Ferrari and Canny): contacts with
// friction, the grasp wrench space as a 6D convex hull (Qhull), force closure,
// and the largest minimum resisted wrench (epsilon); plus the dual grasp's task
// term (sharing the object's weight). Everything is in the object frame o;
// torques are about the object's centre of mass and divided by a length
// `torque_scale_m` so forces and torques are comparable. Qhull stays in
// quality.cpp.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace aerograsp {

using Wrench = Eigen::Matrix<double, 6, 1>;  ///< (force, torque / torque_scale_m)

/// Friction model of a finger contact.
struct FrictionConfig {
  double mu{0.5};     ///< Coulomb coefficient, (0, 2]
  int cone_edges{4};  ///< edges of the polyhedral friction cone, [3, 16]
  /// Soft-finger torsional friction: largest torque about the normal per newton of normal force
  /// (m), [0, 0.05]; 0 = point contacts (a two-finger grasp then cannot resist a torque about the
  /// line through its contacts)
  double torsional_m{0.005};

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// Appends the primitive wrenches of one contact at p_o (m) whose force pushes
/// along the unit inward normal `push_o` (into the object): the cone edges
/// push + mu (cos t u + sin t v), t = 2 pi j / cone_edges (u, v an orthonormal
/// basis of the tangent plane, u from push x (the least aligned axis of o), so
/// edges are deterministic), each with unit normal component (the L1 norm of
/// Ferrari and Canny: the summed normal forces are at most 1); then, when
/// torsional_m > 0, the pure normal push with +- torsional_m of torque about it.
void AppendContactWrenches(const Eigen::Vector3d& p_o, const Eigen::Vector3d& push_o,
                           const Eigen::Vector3d& com_o, double torque_scale_m,
                           const FrictionConfig& friction, std::vector<Wrench>* wrenches);

struct WrenchQuality {
  bool force_closure = false;  ///< the origin is strictly inside the wrench hull
  /// Distance from the origin to the hull's boundary; 0 without force closure
  double epsilon = 0.0;
  int facets = 0;  ///< hull facets (0 when the hull is not 6D)
};

/// Exact quality of a wrench set by a 6D convex hull (Qhull). Sets whose affine
/// hull is not 6D (too few contacts, no friction and no torsion, ...) have no
/// force closure. Precondition: finite wrenches.
WrenchQuality ComputeWrenchQuality(const std::vector<Wrench>& wrenches);

/// A fixed set of unit directions of R^6 for support-function estimates:
/// the 12 +-axis directions, then pseudo-random unit vectors from a fixed
/// seed (deterministic on every platform). count >= 12.
std::vector<Wrench> SupportDirections(int count);

/// h_k = max_i u_k . w_i for each direction u_k: the support function of the
/// wrench hull sampled at the directions (floats: a table per contact pair).
std::vector<float> SupportTable(const std::vector<Wrench>& wrenches,
                                const std::vector<Wrench>& directions);

/// Fast estimate of epsilon for the union of two grasps' wrench sets: the
/// support function of the union's hull is the larger of the two, so
/// min_k max(h_a[k], h_b[k]) over the sampled directions. It is an upper bound
/// of the exact epsilon (it only samples the minimum), and <= 0 proves the
/// union has no force closure. O(count), a few hundred nanoseconds.
double EpsilonUpperBound(const float* h_a, const float* h_b, int count);

/// How well a dual grasp shares the object's weight. With every point
/// projected on the plane normal to gravity (g_o, unit, object frame): t is
/// where the centre of mass falls along the segment from the left grasp centre
/// to the right one, d its distance off that segment's line. The left arm
/// carries 1 - t of the weight and the right t when the centre of mass is
/// between them; outside, one arm would have to push down. Returns
/// (1 - |2t - 1|) / (1 + d / length_scale_m) clamped to [0, 1]: 1 for an
/// even share with the centre of mass on the line between the grasps, 0 when
/// it is not between them. Grasp centres on the same vertical give 0.
struct WeightShare {
  double term = 0.0;        ///< [0, 1]
  double left_share = 0.0;  ///< fraction of the weight on the left arm (1 - t), can be < 0 or > 1
  double offset_m = 0.0;    ///< d
};
WeightShare ComputeWeightShare(const Eigen::Vector3d& left_center_o,
                               const Eigen::Vector3d& right_center_o, const Eigen::Vector3d& com_o,
                               const Eigen::Vector3d& g_o, double length_scale_m);

}  // namespace aerograsp
