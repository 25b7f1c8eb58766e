// Where the vehicle should hold the object for a dual grasp: the object's pose
// in the body frame d at which both arms reach the most grasps that survive
// the errors of flight. A grasp counts for an arm when its contacts lie well
// inside the object along its length (a pose estimate off along the length
// then still puts the pads on it), clear of its faces' edges, and it stays
// feasible with the object moved by the planner's reach margin along each
// axis of d (the vehicle's sway and tracking error move it so while the arms
// servo, and the followed pair is solved again every cycle). A grid search around a nominal
// point, ranked by the arm with fewer such grasps, confirmed by the planner
// (the two arms clear each other on one of them). Pure: a function of the
// planner, the nominal point and the settings.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "grasp/planner.h"

namespace aerograsp {

struct PlacementConfig {
  /// The search runs this far either way of the nominal point along x, y and z of d,
  /// each [0, 0.3] m; all 0: the nominal point is the placement.
  double search_x_m{0.06};
  double search_y_m{0.02};
  double search_z_m{0.08};
  double step_m{0.01};  ///< grid spacing, [0.002, 0.1] m
  /// A grasp counts when both contacts are this far or more from the object's
  /// ends along its longest axis (x of o), [0, 0.1] m, and it stays feasible
  /// with the object moved by the planner's reach_margin_m (rounded to whole
  /// grid steps) either way along each axis of d.
  double end_margin_m{0.025};
  /// The object's yaw in d the search assumes, upright (z of o up, against
  /// d's z), [-pi, pi] rad. pi/2: its long x axis across the vehicle.
  double object_yaw_rad{M_PI / 2};

  /// @throws ConfigError "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
  bool Searches() const { return search_x_m > 0.0 || search_y_m > 0.0 || search_z_m > 0.0; }
};

/// The chosen placement and what the arms have there.
struct Placement {
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();
  /// How strictly a grasp counted: 0 robust through the sway, clear of the
  /// ends and of its faces' edges (ArmGrasp::clear_of_edges); 1 robust and
  /// clear of the ends (no point had level-0 grasps for both arms); 2 robust
  /// only; 3 none anywhere (dMo is then the nominal point).
  int level = 3;
  /// Per arm (left, right): the grasps that count at dMo.
  int robust_pairs[2] = {0, 0};
  /// Ranked dual grasps at dMo (GraspPlanner::Plan) of two grasps that count.
  int dual_grasps = 0;
  /// The planner's first choice at dMo is such a dual grasp.
  bool first_choice_counts = false;
  /// Per arm: the grasps that count at the nominal point.
  int nominal_robust_pairs[2] = {0, 0};
  int points = 0;  ///< grid points scored
};

/// The pose of o in d upright at yaw `object_yaw_rad`, its origin at p_d_m.
Eigen::Isometry3d UprightDmo(const Eigen::Vector3d& p_d_m, double object_yaw_rad);

/// Per contact pair: both contacts end_margin_m or more from the mesh's
/// bounding box faces across its x axis (the object's ends).
std::vector<bool> PairsClearOfEnds(const TriangleMesh& mesh_o, const ContactSet& contacts,
                                   double end_margin_m);

/// The placement around `nominal_dto_m` (the origin of o in d): the grid
/// points ranked by the counted grasps of the arm with fewer (ties: of both,
/// then nearer the nominal point), and of the best few the first where the
/// planner's first choice is a dual grasp of two counted ones (else the first
/// where it ranks the most such); the arms at q_left,
/// q_right (their home). A grasp counts at the strictest level (Placement::level)
/// at which both arms have one somewhere in the search.
Placement ChoosePlacement(const GraspPlanner& planner, const Eigen::Vector3d& nominal_dto_m,
                          const PlacementConfig& config, const Eigen::VectorXd& q_left,
                          const Eigen::VectorXd& q_right);

}  // namespace aerograsp
