// Pose errors split the way the arms can meet them (position, then the approach
// axis z, then the roll about it) and a damped-least-squares inverse kinematics
// with the same task priorities and joint-limit clamping. The servo uses the IK
// to find a joint goal in the right branch before it moves (servo/arm_servo.h).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/arm_ik.h"
#include "core/arm_model.h"
#include "servo/dls.h"

namespace aerograsp {

/// The end effector e against the goal g (both in the arm base b). The
/// orientation error is split into a swing, the smallest rotation taking the
/// approach axis z_e onto z_g, and the roll about z_g left after it.
struct ApproachError {
  Eigen::Vector3d position_b = Eigen::Vector3d::Zero();  ///< p_g - p_e in b (m)
  Eigen::Vector3d swing_b = Eigen::Vector3d::Zero();     ///< axis * angle of the swing, in b (rad)
  double approach_rad = 0.0;                             ///< angle between z_e and z_g, [0, pi]
  double roll_rad = 0.0;                                 ///< signed roll about z_g, [-pi, pi]
};
/// Both poses must be rigid transforms. At z_e = -z_g the swing turns about x_e.
ApproachError ComputeApproachError(const Eigen::Isometry3d& bMe, const Eigen::Isometry3d& bMg);

/// Joint positions (rad) drawn uniformly within the arm's limits, joint by joint.
Eigen::VectorXd DrawJointsWithinLimits(const ArmModel& arm, std::mt19937* rng);

/// When a pose counts as reached. A 4-DoF arm meets position and approach axis
/// (its roll joint j3 sets the roll); the roll tolerance may be set to pi to
/// leave the roll out.
struct PoseTolerance {
  double position_m{1e-3};    ///< |p_g - p_e|, (0, 1] m
  double approach_rad{0.01};  ///< angle between the approach axes, (0, pi] rad
  double roll_rad{0.02};      ///< roll about the approach axis, (0, pi] rad

  bool Met(const ApproachError& error) const {
    return error.position_b.norm() <= position_m && error.approach_rad <= approach_rad &&
           std::abs(error.roll_rad) <= roll_rad;
  }
  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

struct ApproachIkOptions {
  int iterations_per_seed{60};  ///< damped Newton iterations from one seed, [1, 10000]
  int random_seeds{24};         ///< seeds drawn in the limits after the given ones, [0, 10000]
  double max_step_rad{0.4};     ///< largest joint change per iteration, (0, 3] rad
  PoseTolerance tolerance{1e-4, 1e-3, 1e-3};  ///< what a solution must meet
  DampingOptions damping{0.02, 0.02};         ///< max_damping is also capped by the error (m)

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

struct ApproachIkResult {
  bool converged = false;
  Eigen::VectorXd q;    ///< the solution (rad), within limits; the best iterate when not converged
  ApproachError error;  ///< at q
  int iterations = 0;   ///< in all seeds
};

/// The iterations from one seed, one at a time (ApproachIk::Iterate): a search
/// can spread them over cycles and stop anywhere.
struct ApproachIkRun {
  Eigen::VectorXd q;      ///< the next iterate (rad)
  ApproachIkResult best;  ///< the best iterate so far; `converged` once done and solved
  double best_badness = INFINITY;
  int since_better = 0;  ///< iterations without a better iterate
  bool done = false;     ///< converged, stalled or out of iterations
};

/// Damped least squares IK of one arm: each iteration solves position and the
/// weighted approach/roll error (scaled 0.1 m/rad) as one least-squares system,
/// clamps joints at their limits and solves again without the clamped joints
/// (so a joint at a limit does not stall the others). A solution must meet the
/// position and the weighted orientation: a pose a 4-DoF arm can reach only in
/// position is unreachable for it.
class ApproachIk {
 public:
  /// `arm` must outlive the solver. orientation_weights: of the error about the
  /// tool's x, y (approach) and z (roll) axes, [0, 1].
  ApproachIk(const ArmModel& arm, const ApproachIkOptions& options,
             const Eigen::Vector3d& orientation_weights = Eigen::Vector3d::Ones());

  /// Iterates from one seed (clamped into the limits) toward bMg.
  ApproachIkResult SolveFrom(const Eigen::Isometry3d& bMg, const Eigen::VectorXd& q_seed,
                             int max_iterations) const;

  /// A run from q_seed (clamped into the limits), before its first iteration.
  ApproachIkRun StartFrom(const Eigen::VectorXd& q_seed) const;
  /// One damped Newton iteration of `run` toward bMg (SolveFrom is these
  /// iterations in a row): sets run->done when the iterate converged, stalled
  /// or reached max_iterations. Does nothing on a run that is done.
  void Iterate(const Eigen::Isometry3d& bMg, int max_iterations, ApproachIkRun* run) const;

  /// The error the solver drives to zero, with weights applied (for tests).
  bool Converged(const ApproachError& error) const;

  /// True when ClosedFormSeeds are every solution a search could find: the
  /// arm's closed form solves the full pose and the error weighs every
  /// orientation axis (the 6-DoF arm). Other seeds then only cost time.
  bool closed_form_complete() const;

  /// Seeds from the arm's closed form (core/arm_ik.h, SolveClosedForm), the
  /// nearest q first: the 6-DoF arm's exact solutions of bMg (each converges
  /// in one iteration), the 4-DoF arm's solutions of its position and closing
  /// axis. Empty for an arm without a closed form.
  std::vector<Eigen::VectorXd> ClosedFormSeeds(const Eigen::Isometry3d& bMg,
                                               const Eigen::VectorXd& q) const;

 private:
  const ArmModel& arm_;
  ArmIk closed_form_;
  ApproachIkOptions options_;
  Eigen::Vector3d weights_;
};

}  // namespace aerograsp
