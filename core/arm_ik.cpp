#include "core/arm_ik.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/transforms.h"

namespace aerograsp {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGeomTol = 1e-9;  // structure checks of the chain (m or unit vectors)

/// Signed angle (rad) turning v1 into v2 about the unit axis k (both ⊥ k).
double SignedAngle(const Eigen::Vector3d& v1, const Eigen::Vector3d& v2, const Eigen::Vector3d& k) {
  return std::atan2(k.dot(v1.cross(v2)), v1.dot(v2));
}

double WrapPi(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0.0) a += 2.0 * kPi;
  return a - kPi;
}

/// A unit vector perpendicular to the unit vector x (deterministic).
Eigen::Vector3d AnyPerpendicular(const Eigen::Vector3d& x) {
  Eigen::Index i;
  x.cwiseAbs().minCoeff(&i);
  return x.cross(Eigen::Vector3d::Unit(i)).normalized();
}

}  // namespace

ArmIk::ArmIk(const ArmModel& model, const IkOptions& options) : model_(model), options_(options) {
  AnalyseChain();
}

void ArmIk::AnalyseChain() {
  analytic_ = false;
  if (model_.dof() != 4) return;
  for (int i = 0; i < 4; ++i) {
    if (model_.joint_type(i) != ArmModel::JointType::kRevolute) return;
  }
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(4);
  std::vector<Eigen::Isometry3d> bMs;
  model_.SegmentPoses(q0, &bMs);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> J = model_.Jacobian(q0);
  Eigen::Vector3d o[4];
  for (int i = 0; i < 4; ++i) {
    w_[i] = J.block<3, 1>(3, i).normalized();
    o[i] = bMs[i + 1].translation();
  }
  const Eigen::Isometry3d& bMe0 = bMs.back();
  const Eigen::Vector3d tool = bMe0.translation();
  o1_ = o[1];
  l1_ = (o[2] - o[1]).norm();
  l2_ = (tool - o[2]).norm();
  if (l1_ < 1e-6 || l2_ < 1e-6) return;
  u0_ = (o[2] - o[1]) / l1_;
  f0_ = (tool - o[2]) / l2_;
  xe0_ = bMe0.linear().col(0);
  const Eigen::Vector3d ze0 = bMe0.linear().col(2);
  const bool yaw_through_shoulder = (o[1] - o[0]).cross(w_[0]).norm() < kGeomTol;
  const bool pitches_parallel = w_[1].cross(w_[2]).norm() < kGeomTol;
  const bool pitch_perpendicular = std::abs(w_[0].dot(w_[1])) < kGeomTol;
  const bool planar = std::abs(u0_.dot(w_[1])) < kGeomTol && std::abs(f0_.dot(w_[1])) < kGeomTol;
  const bool roll_on_forearm =
      w_[3].cross(f0_).norm() < kGeomTol && (o[3] - o[2]).cross(f0_).norm() < kGeomTol;
  const bool approach_on_forearm = ze0.cross(f0_).norm() < kGeomTol;
  if (!(yaw_through_shoulder && pitches_parallel && pitch_perpendicular && planar &&
        roll_on_forearm && approach_on_forearm)) {
    return;
  }
  h0_ = w_[1].cross(w_[0]).normalized();
  approach_sign_ = ze0.dot(f0_) > 0.0 ? 1.0 : -1.0;
  analytic_ = true;
}

bool ArmIk::FitLimits(Eigen::VectorXd* q) const {
  const Eigen::VectorXd& lo = model_.lower_limits();
  const Eigen::VectorXd& hi = model_.upper_limits();
  for (int i = 0; i < q->size(); ++i) {
    double& v = (*q)[i];
    if (v < lo[i]) v += 2.0 * kPi;
    if (v > hi[i]) v -= 2.0 * kPi;
    if (v < lo[i] || v > hi[i]) return false;
  }
  return true;
}

bool ArmIk::CheckPosition(const Eigen::VectorXd& q, const Eigen::Vector3d& p_b) const {
  return (model_.ForwardKinematics(q).translation() - p_b).norm() <= options_.position_tolerance_m;
}

void ArmIk::SortBySeed(const Eigen::VectorXd& q_seed,
                       std::vector<Eigen::VectorXd>* solutions) const {
  std::stable_sort(solutions->begin(), solutions->end(),
                   [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
                     return (a - q_seed).squaredNorm() < (b - q_seed).squaredNorm();
                   });
  // Drop duplicates (e.g. a zero elbow discriminant gives the same solution twice).
  auto last = std::unique(solutions->begin(), solutions->end(),
                          [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
                            return (a - b).cwiseAbs().maxCoeff() < 1e-9;
                          });
  solutions->erase(last, solutions->end());
}

void ArmIk::AnalyticPosition(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                             double seed_roll, std::vector<Eigen::VectorXd>* solutions) const {
  const Eigen::Vector3d v = p_b - o1_;
  Eigen::Vector3d v_perp = v - v.dot(w_[0]) * w_[0];
  const Eigen::Vector3d h = v_perp.norm() > kGeomTol ? Eigen::Vector3d(v_perp.normalized()) : h0_;
  for (double yaw_sign : {1.0, -1.0}) {
    const double q0 = SignedAngle(h0_, yaw_sign * h, w_[0]);
    const Eigen::Matrix3d R0 = Eigen::AngleAxisd(q0, w_[0]).toRotationMatrix();
    const Eigen::Vector3d p1 = R0.transpose() * v;  // target in the q = 0 arm plane
    const double r = p1.norm();
    if (r < kGeomTol) continue;
    const double along = (l1_ * l1_ - l2_ * l2_ + r * r) / (2.0 * r);
    const double across_sq = l1_ * l1_ - along * along;
    if (across_sq < -1e-12) continue;  // out of reach
    const double across = std::sqrt(std::max(0.0, across_sq));
    const Eigen::Vector3d p_hat = p1 / r;
    const Eigen::Vector3d n_hat = w_[1].cross(p_hat);
    for (double elbow_sign : {1.0, -1.0}) {
      if (elbow_sign < 0.0 && across == 0.0) break;
      const Eigen::Vector3d e1 = along * p_hat + elbow_sign * across * n_hat;
      const double q1 = SignedAngle(u0_, e1.normalized(), w_[1]);
      const Eigen::Vector3d f1 = (p1 - e1).normalized();
      const Eigen::Vector3d f2 = Eigen::AngleAxisd(-q1, w_[1]) * f1;
      const double q2 = SignedAngle(f0_, f2, w_[2]);
      const Eigen::Matrix3d R012 =
          R0 * Eigen::AngleAxisd(q1, w_[1]).toRotationMatrix() * Eigen::AngleAxisd(q2, w_[2]);
      const Eigen::Vector3d f = R012 * f0_;
      const Eigen::Vector3d x_perp = x_b - x_b.dot(f) * f;
      double rolls[2] = {seed_roll, seed_roll};
      int n_rolls = 1;
      if (x_perp.norm() > 1e-9) {
        const Eigen::Vector3d x3 = R012.transpose() * x_perp.normalized();
        rolls[0] = SignedAngle(xe0_, x3, w_[3]);
        rolls[1] = WrapPi(rolls[0] + kPi);  // the fingers are symmetric: -x is as good
        n_rolls = 2;
      }
      for (int k = 0; k < n_rolls; ++k) {
        Eigen::VectorXd q(4);
        q << WrapPi(q0), WrapPi(q1), WrapPi(q2), rolls[k];
        if (FitLimits(&q) && CheckPosition(q, p_b)) solutions->push_back(q);
      }
    }
  }
}

int ArmIk::SolvePosition(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                         const Eigen::VectorXd& q_seed,
                         std::vector<Eigen::VectorXd>* solutions) const {
  assert(q_seed.size() == model_.dof());
  solutions->clear();
  if (!p_b.allFinite() || !x_b.allFinite()) return 0;
  if (analytic_) {
    AnalyticPosition(p_b, x_b, q_seed[3], solutions);
    SortBySeed(q_seed, solutions);
    return static_cast<int>(solutions->size());
  }
  // Numeric, position only.
  Eigen::VectorXd q = model_.Clamp(q_seed);
  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  const double lambda_sq = options_.damping * options_.damping;
  for (int it = 0; it < options_.max_iterations; ++it) {
    model_.Kinematics(q, &bMe, &J);
    const Eigen::Vector3d e = p_b - bMe.translation();
    if (e.norm() <= options_.position_tolerance_m) {
      solutions->push_back(q);
      return 1;
    }
    const Eigen::MatrixXd Jp = J.topRows<3>();
    const Eigen::Matrix3d A = Jp * Jp.transpose() + lambda_sq * Eigen::Matrix3d::Identity();
    q = model_.Clamp(q + Jp.transpose() * A.ldlt().solve(e));
  }
  return 0;
}

bool ArmIk::SolvePoseNumeric(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                             Eigen::VectorXd* q_out) const {
  assert(q_seed.size() == model_.dof());
  if (!bMe_target.matrix().allFinite()) return false;
  Eigen::VectorXd q = model_.Clamp(q_seed);
  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;
  Eigen::Matrix<double, 6, 1> e;
  const double lambda_sq = options_.damping * options_.damping;
  for (int it = 0; it <= options_.max_iterations; ++it) {
    model_.Kinematics(q, &bMe, &J);
    e.head<3>() = bMe_target.translation() - bMe.translation();
    e.tail<3>() = ThetaU(bMe_target.linear() * bMe.linear().transpose());
    if (e.head<3>().norm() <= options_.position_tolerance_m &&
        e.tail<3>().norm() <= options_.orientation_tolerance_rad) {
      if (!model_.WithinLimits(q)) return false;
      *q_out = q;
      return true;
    }
    if (it == options_.max_iterations) break;
    const Eigen::Matrix<double, 6, 6> A =
        J * J.transpose() + lambda_sq * Eigen::Matrix<double, 6, 6>::Identity();
    q = model_.Clamp(q + J.transpose() * A.ldlt().solve(e));
  }
  return false;
}

int ArmIk::SolveGraspAxis(const Eigen::Vector3d& c_b, const Eigen::Vector3d& x_b,
                          double depth_min_m, double depth_max_m, const Eigen::VectorXd& q_seed,
                          std::vector<GraspAxisSolution>* solutions) const {
  assert(q_seed.size() == model_.dof());
  solutions->clear();
  if (!c_b.allFinite() || !x_b.allFinite() || x_b.norm() < 1e-12 || depth_min_m > depth_max_m) {
    return 0;
  }
  const Eigen::Vector3d x = x_b.normalized();
  auto add = [&](const Eigen::VectorXd& q, double depth) {
    GraspAxisSolution s;
    s.q = q;
    s.bMe = model_.ForwardKinematics(q);
    s.depth_m = depth;
    solutions->push_back(std::move(s));
  };

  if (analytic_) {
    // Approach directions a ⊥ x whose line through c_b meets the yaw axis, and
    // depths that put the elbow at l1 from the shoulder: |v + k a| = l1 with
    // k = depth - approach_sign * l2 (the elbow is at c_b + k a).
    const Eigen::Vector3d v = c_b - o1_;
    const Eigen::Vector3d m = w_[0].cross(v);                 // normal of the yaw plane through c_b
    if (m.norm() < kGeomTol) return 0;                        // contact centre on the yaw axis
    std::vector<std::pair<Eigen::Vector3d, double>> targets;  // (approach, depth)
    const Eigen::Vector3d xm = x.cross(m);
    if (xm.norm() > 1e-6 * m.norm()) {
      for (double s : {1.0, -1.0}) {
        const Eigen::Vector3d a = s * xm.normalized();
        const double b = v.dot(a);
        const double disc = b * b - v.squaredNorm() + l1_ * l1_;
        if (disc < 0.0) continue;
        for (double root : {-b + std::sqrt(disc), -b - std::sqrt(disc)}) {
          const double depth = root + approach_sign_ * l2_;
          if (depth >= depth_min_m && depth <= depth_max_m) targets.emplace_back(a, depth);
        }
      }
    } else {
      // The closing axis is normal to the yaw plane: every approach in the plane
      // is perpendicular to it; sample the depth and solve for the approach.
      const Eigen::Vector3d h = (m.cross(w_[0])).normalized();  // in-plane, ⊥ yaw axis
      const double A = v.dot(w_[0]), B = v.dot(h), R = std::hypot(A, B);
      constexpr int kDepthSamples = 3;
      for (int i = 0; i < kDepthSamples; ++i) {
        const double depth =
            depth_min_m + (depth_max_m - depth_min_m) * i / static_cast<double>(kDepthSamples - 1);
        const double k = depth - approach_sign_ * l2_;
        if (std::abs(k) < kGeomTol || R < kGeomTol) continue;
        const double beta = (l1_ * l1_ - v.squaredNorm() - k * k) / (2.0 * k);
        if (std::abs(beta) > R) continue;
        const double phi0 = std::atan2(B, A), dphi = std::acos(beta / R);
        for (double phi : {phi0 + dphi, phi0 - dphi}) {
          targets.emplace_back(std::cos(phi) * w_[0] + std::sin(phi) * h, depth);
        }
      }
    }
    std::vector<Eigen::VectorXd> qs;
    for (const auto& [a, depth] : targets) {
      AnalyticPosition(c_b + depth * a, x, q_seed[3], &qs);
      for (const Eigen::VectorXd& q : qs) {
        const Eigen::Isometry3d bMe = model_.ForwardKinematics(q);
        // Keep the branches whose approach is the one solved for (the other
        // elbow branch reaches the same point with another approach).
        if (bMe.linear().col(2).dot(a) > std::cos(options_.orientation_tolerance_rad)) {
          add(q, depth);
        }
      }
      qs.clear();
    }
  } else {
    const Eigen::Vector3d e1 = AnyPerpendicular(x), e2 = x.cross(e1);
    const double depth = 0.5 * (depth_min_m + depth_max_m);
    const int n = std::max(1, options_.approach_samples);
    for (int i = 0; i < n; ++i) {
      const double phi = 2.0 * kPi * i / n;
      const Eigen::Vector3d a = std::cos(phi) * e1 + std::sin(phi) * e2;
      for (double s : {1.0, -1.0}) {
        Eigen::Isometry3d bMe = Eigen::Isometry3d::Identity();
        bMe.linear().col(0) = s * x;
        bMe.linear().col(1) = a.cross(s * x);
        bMe.linear().col(2) = a;
        bMe.translation() = c_b + depth * a;
        Eigen::VectorXd q;
        if (SolvePoseNumeric(bMe, q_seed, &q)) {
          add(q, depth);
          break;
        }
      }
    }
  }
  std::stable_sort(solutions->begin(), solutions->end(),
                   [&](const GraspAxisSolution& a, const GraspAxisSolution& b) {
                     return (a.q - q_seed).squaredNorm() < (b.q - q_seed).squaredNorm();
                   });
  return static_cast<int>(solutions->size());
}

}  // namespace aerograsp
