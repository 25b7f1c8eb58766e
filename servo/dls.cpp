#include "servo/dls.h"

#include <Eigen/SVD>
#include <cmath>

namespace aerograsp {
namespace {

double Damping(double min_singular, const DampingOptions& options) {
  if (min_singular >= options.singular_threshold) return 0.0;
  const double r = min_singular / options.singular_threshold;
  return options.max_damping * std::sqrt(1.0 - r * r);
}

// A damped inverse applied to e, from an SVD; also returns the null-space projector when asked.
DlsSolution Solve(const Eigen::MatrixXd& J, const Eigen::VectorXd& e, const DampingOptions& options,
                  Eigen::MatrixXd* null_projector) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  const Eigen::Index n = J.cols();
  const Eigen::Index k = s.size();  // min(m, n)
  // J J^T is m x m: its conditioning is that of the k = min(m, n) singular values.
  const double s_min = k == 0 ? 0.0 : s[k - 1];
  const double lambda = Damping(s_min, options);
  Eigen::VectorXd gains(k);
  for (Eigen::Index i = 0; i < k; ++i) gains[i] = s[i] / (s[i] * s[i] + lambda * lambda);
  const Eigen::VectorXd Ute = svd.matrixU().leftCols(k).transpose() * e;
  DlsSolution solution;
  solution.dq = svd.matrixV().leftCols(k) * gains.cwiseProduct(Ute);
  solution.min_singular = s_min;
  solution.damping = lambda;
  if (null_projector) {
    // Undamped projector onto the null space of J (directions with s_i ~ 0 count as null).
    const double tolerance = 1e-9 * (k > 0 ? s[0] : 1.0);
    Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n);
    for (Eigen::Index i = 0; i < k; ++i) {
      if (s[i] > tolerance) P -= svd.matrixV().col(i) * svd.matrixV().col(i).transpose();
    }
    *null_projector = P;
  }
  return solution;
}

}  // namespace

DlsSolution SolveDampedLeastSquares(const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
                                    const DampingOptions& options) {
  return Solve(J, e, options, nullptr);
}

DlsSolution SolvePrioritized(const Eigen::MatrixXd& J1, const Eigen::VectorXd& e1,
                             const Eigen::MatrixXd& J2, const Eigen::VectorXd& e2,
                             const DampingOptions& options) {
  Eigen::MatrixXd N1;
  DlsSolution primary = Solve(J1, e1, options, &N1);
  const DlsSolution secondary = Solve(J2 * N1, e2 - J2 * primary.dq, options, nullptr);
  primary.dq += N1 * secondary.dq;
  return primary;
}

}  // namespace aerograsp
