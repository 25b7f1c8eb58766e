#include "servo/ik.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/config.h"

namespace aerograsp {

ApproachError ComputeApproachError(const Eigen::Isometry3d& bMe, const Eigen::Isometry3d& bMg) {
  ApproachError error;
  error.position_b = bMg.translation() - bMe.translation();
  const Eigen::Vector3d z_e = bMe.linear().col(2), z_g = bMg.linear().col(2);
  const Eigen::Vector3d cross = z_e.cross(z_g);
  const double sin_a = cross.norm(), cos_a = z_e.dot(z_g);
  error.approach_rad = std::atan2(sin_a, cos_a);
  // Swing axis: along z_e x z_g; when they are (anti)parallel any axis normal to z_e does.
  const Eigen::Vector3d axis =
      sin_a > 1e-12 ? Eigen::Vector3d(cross / sin_a) : Eigen::Vector3d(bMe.linear().col(0));
  error.swing_b = axis * error.approach_rad;
  const Eigen::Vector3d x_swung = Eigen::AngleAxisd(error.approach_rad, axis) * bMe.linear().col(0);
  const Eigen::Vector3d x_g = bMg.linear().col(0);
  error.roll_rad = std::atan2(x_swung.cross(x_g).dot(z_g), x_swung.dot(x_g));
  return error;
}

Eigen::VectorXd DrawJointsWithinLimits(const ArmModel& arm, std::mt19937* rng) {
  Eigen::VectorXd q(arm.dof());
  for (int i = 0; i < arm.dof(); ++i) {
    q[i] =
        std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(*rng);
  }
  return q;
}

void PoseTolerance::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "position_m", position_m, 1e-9, 1.0, "m");
  CheckRange(source, prefix + "approach_rad", approach_rad, 1e-9, M_PI, "rad");
  CheckRange(source, prefix + "roll_rad", roll_rad, 1e-9, M_PI, "rad");
}

void ApproachIkOptions::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "iterations_per_seed", iterations_per_seed, 1, 10000, "");
  CheckRange(source, prefix + "random_seeds", random_seeds, 0, 10000, "");
  CheckRange(source, prefix + "max_step_rad", max_step_rad, 1e-6, 3.0, "rad");
  tolerance.Validate(source, prefix + "tolerance.");
  CheckRange(source, prefix + "damping.singular_threshold", damping.singular_threshold, 1e-9, 1.0,
             "");
  CheckRange(source, prefix + "damping.max_damping", damping.max_damping, 1e-9, 1.0, "");
}

ApproachIk::ApproachIk(const ArmModel& arm, const ApproachIkOptions& options,
                       const Eigen::Vector3d& orientation_weights)
    : arm_(arm), closed_form_(arm), options_(options), weights_(orientation_weights) {
  options_.Validate("ik options", "ik.");
}

std::vector<Eigen::VectorXd> ApproachIk::ClosedFormSeeds(const Eigen::Isometry3d& bMg,
                                                         const Eigen::VectorXd& q) const {
  std::vector<Eigen::VectorXd> seeds;
  if (q.size() == arm_.dof() && q.allFinite()) closed_form_.SolveClosedForm(bMg, q, &seeds);
  return seeds;
}

bool ApproachIk::closed_form_complete() const {
  return closed_form_.closed_form_solves_pose() && weights_.minCoeff() > 0.0;
}

bool ApproachIk::Converged(const ApproachError& error) const {
  const PoseTolerance& tol = options_.tolerance;
  if (error.position_b.norm() > tol.position_m) return false;
  if (weights_.head<2>().maxCoeff() > 0.0 && error.approach_rad > tol.approach_rad) return false;
  return !(weights_.z() > 0.0 && std::abs(error.roll_rad) > tol.roll_rad);
}

namespace {

// Metres per radian of orientation error in the IK's least-squares system.
constexpr double kRotationScaleM = 0.1;

// A scalar to rank non-converged iterates: metres plus radians at 0.1 m/rad.
double Badness(const ApproachError& e) {
  return e.position_b.norm() + kRotationScaleM * (e.approach_rad + std::abs(e.roll_rad));
}

}  // namespace

ApproachIkRun ApproachIk::StartFrom(const Eigen::VectorXd& q_seed) const {
  ApproachIkRun run;
  run.q = arm_.Clamp(q_seed);
  run.best.q = run.q;
  return run;
}

void ApproachIk::Iterate(const Eigen::Isometry3d& bMg, int max_iterations,
                         ApproachIkRun* run) const {
  if (run->done) return;
  if (run->best.iterations >= max_iterations) {
    run->done = true;
    return;
  }
  const int n = arm_.dof();
  Eigen::VectorXd& q = run->q;
  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, n);
  arm_.Kinematics(q, &bMe, &J);
  const ApproachError error = ComputeApproachError(bMe, bMg);
  ++run->best.iterations;
  const double badness = Badness(error);
  if (badness < run->best_badness - 1e-12) {
    run->best_badness = badness;
    run->best.q = q;
    run->best.error = error;
    run->since_better = 0;
  } else if (++run->since_better > 15) {
    run->done = true;  // stalled: a local minimum of this seed
    return;
  }
  if (Converged(error)) {
    run->best.converged = true;
    run->done = true;
    return;
  }
  // Position and weighted orientation in one least-squares system, the
  // orientation rows scaled to metres: near the stretched and yaw-axis
  // singularities of the 4-DoF arm only the approach axis tells the
  // position's branches apart, so it must act on every joint.
  const Eigen::Matrix3d bRe = bMe.linear();
  const Eigen::Matrix3d W_b = kRotationScaleM * bRe * weights_.asDiagonal() * bRe.transpose();
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = error.position_b;
  e.tail<3>() = W_b * (error.swing_b + error.roll_rad * bRe.col(2));
  Eigen::MatrixXd Js(6, n);
  Js.topRows<3>() = J.topRows<3>();
  Js.bottomRows<3>() = W_b * J.bottomRows<3>();
  // Damping no larger than the error (Levenberg-Marquardt style): robust far
  // away, and it fades near a solution that sits close to a singularity,
  // where a fixed damping would slow the last iterations to a crawl.
  DampingOptions damping = options_.damping;
  damping.max_damping = std::clamp(e.norm(), 1e-9, damping.max_damping);
  // Clamping loop: a joint the step would push past a limit is set onto the
  // limit, its motion removed from the errors, and the rest solved again.
  std::vector<bool> clamped(n, false);
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(n), clamped_dq = Eigen::VectorXd::Zero(n);
  for (int pass = 0; pass <= n; ++pass) {
    dq = SolveDampedLeastSquares(Js, e, damping).dq;
    const double largest = dq.cwiseAbs().maxCoeff();
    if (largest > options_.max_step_rad) dq *= options_.max_step_rad / largest;
    bool clamped_any = false;
    for (int i = 0; i < n; ++i) {
      if (clamped[i]) continue;
      const double next = q[i] + dq[i];
      const double onto = std::clamp(next, arm_.lower_limits()[i], arm_.upper_limits()[i]);
      if (onto == next) continue;
      clamped[i] = clamped_any = true;
      clamped_dq[i] = onto - q[i];
      e -= Js.col(i) * clamped_dq[i];
      Js.col(i).setZero();
    }
    if (!clamped_any) break;
  }
  for (int i = 0; i < n; ++i) {
    if (clamped[i]) dq[i] = clamped_dq[i];
  }
  q = arm_.Clamp(q + dq);
  if (run->best.iterations >= max_iterations) run->done = true;
}

ApproachIkResult ApproachIk::SolveFrom(const Eigen::Isometry3d& bMg, const Eigen::VectorXd& q_seed,
                                       int max_iterations) const {
  ApproachIkRun run = StartFrom(q_seed);
  while (!run.done) Iterate(bMg, max_iterations, &run);
  return run.best;
}

}  // namespace aerograsp
