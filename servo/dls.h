// Damped least squares with task priorities: the numeric core of the arm
// servo. No ViSP here: the twist to follow comes from servo/pbvs.h.
#pragma once

#include <Eigen/Core>

namespace aerograsp {

/// Damping that grows only near singularities (Nakamura & Hanafusa /
/// Maciejewski): lambda^2 = (1 - (s_min / threshold)^2) * max_damping^2 when the
/// smallest singular value s_min is below `threshold`, else 0.
struct DampingOptions {
  double singular_threshold = 0.04;  ///< s_min below which damping starts (> 0)
  double max_damping = 0.04;         ///< damping at a singularity (> 0)
};

/// Result of one damped solve.
struct DlsSolution {
  Eigen::VectorXd dq;         ///< joint increment (or velocity)
  double min_singular = 0.0;  ///< smallest singular value of the (projected) Jacobian
  double damping = 0.0;       ///< lambda used
};

/// dq = J^T (J J^T + lambda^2 I)^-1 e, computed by SVD so that it is exact for any
/// rank: dq = sum_i s_i / (s_i^2 + lambda^2) v_i u_i^T e. J is m x n, e has m rows.
/// (The paper's Eq. 9 writes [J^T J + lambda^2 I]^-1 e, which does not even have the
/// right size unless m = n; this is the damped least-squares solution.)
DlsSolution SolveDampedLeastSquares(const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
                                    const DampingOptions& options);

/// Two-level task priority (Siciliano & Slotine with damped inverses): the
/// primary task (J1, e1) is met as well as possible, the secondary (J2, e2) only
/// within the primary's null space:
///   dq1 = DLS(J1, e1),  dq = dq1 + DLS(J2 N1, e2 - J2 dq1),  N1 = I - J1^+ J1.
/// The returned min_singular and damping are those of the primary task.
DlsSolution SolvePrioritized(const Eigen::MatrixXd& J1, const Eigen::VectorXd& e1,
                             const Eigen::MatrixXd& J2, const Eigen::VectorXd& e2,
                             const DampingOptions& options);

}  // namespace aerograsp
