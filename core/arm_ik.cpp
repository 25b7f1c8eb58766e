#include "core/arm_ik.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

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
  kind_ = Kind::kNumeric;
  const int n = model_.dof();
  if (n != 4 && n != 6) return;
  for (int i = 0; i < n; ++i) {
    if (model_.joint_type(i) != ArmModel::JointType::kRevolute) return;
  }
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Isometry3d> bMs;
  model_.SegmentPoses(q0, &bMs);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> J = model_.Jacobian(q0);
  Eigen::Vector3d o[6];
  for (int i = 0; i < n; ++i) {
    w_[i] = J.block<3, 1>(3, i).normalized();
    o[i] = bMs[i + 1].translation();
  }
  const Eigen::Isometry3d& bMe0 = bMs.back();
  const Eigen::Vector3d tool = bMe0.translation();
  // The forearm's end: the tool point (4 joints) or where the wrist axes meet.
  Eigen::Vector3d end = tool;
  if (n == 6) {
    // Closest points of the lines (o3, w3) and (o4, w4).
    const double b = w_[3].dot(w_[4]);
    const Eigen::Vector3d r = o[3] - o[4];
    const double d = w_[3].dot(r), e = w_[4].dot(r), den = 1.0 - b * b;
    if (den < 1e-9) return;  // parallel wrist axes
    const Eigen::Vector3d p3 = o[3] + ((b * e - d) / den) * w_[3];
    const Eigen::Vector3d p4 = o[4] + ((e - b * d) / den) * w_[4];
    if ((p3 - p4).norm() > kGeomTol || (p3 - o[5]).cross(w_[5]).norm() > kGeomTol) return;
    if (w_[4].cross(w_[5]).norm() < 1e-6) return;
    end = p3;
  }
  o1_ = o[1];
  l1_ = (o[2] - o[1]).norm();
  l2_ = (end - o[2]).norm();
  if (l1_ < 1e-6 || l2_ < 1e-6) return;
  u0_ = (o[2] - o[1]) / l1_;
  f0_ = (end - o[2]) / l2_;
  xe0_ = bMe0.linear().col(0);
  const Eigen::Vector3d ze0 = bMe0.linear().col(2);
  const bool yaw_through_shoulder = (o[1] - o[0]).cross(w_[0]).norm() < kGeomTol;
  const bool pitches_parallel = w_[1].cross(w_[2]).norm() < kGeomTol;
  const bool pitch_perpendicular = std::abs(w_[0].dot(w_[1])) < kGeomTol;
  const bool planar = std::abs(u0_.dot(w_[1])) < kGeomTol && std::abs(f0_.dot(w_[1])) < kGeomTol;
  if (!(yaw_through_shoulder && pitches_parallel && pitch_perpendicular && planar)) return;
  h0_ = w_[1].cross(w_[0]).normalized();
  if (n == 6) {
    Re0_ = bMe0.linear();
    d_e_ = Re0_.transpose() * (tool - end);
    kind_ = Kind::kSphericalWrist;
    return;
  }
  const bool roll_on_forearm =
      w_[3].cross(f0_).norm() < kGeomTol && (o[3] - o[2]).cross(f0_).norm() < kGeomTol;
  const bool approach_on_forearm = ze0.cross(f0_).norm() < kGeomTol;
  if (!(roll_on_forearm && approach_on_forearm)) return;
  approach_sign_ = ze0.dot(f0_) > 0.0 ? 1.0 : -1.0;
  kind_ = Kind::kYawPitchPitchRoll;
}

bool ArmIk::FitLimit(int i, double* v) const {
  const double lo = model_.lower_limits()[i], hi = model_.upper_limits()[i];
  if (*v < lo) *v += 2.0 * kPi;
  if (*v > hi) *v -= 2.0 * kPi;
  return !(*v < lo || *v > hi);
}

bool ArmIk::FitLimits(Eigen::VectorXd* q) const {
  for (int i = 0; i < q->size(); ++i) {
    if (!FitLimit(i, &(*q)[i])) return false;
  }
  return true;
}

bool ArmIk::Fits(int i, double angle) const {
  double v = WrapPi(angle);
  return FitLimit(i, &v);
}

double ArmIk::WristMargin(const Eigen::VectorXd& q) const {
  if (kind_ != Kind::kSphericalWrist) return std::numeric_limits<double>::infinity();
  double margin = std::abs(std::remainder(q[4], kPi));
  for (int i = 3; i < 6; ++i) {
    margin = std::min({margin, q[i] - model_.lower_limits()[i], model_.upper_limits()[i] - q[i]});
  }
  return margin;
}

bool ArmIk::InReach(double r_min, double r_max) const {
  // PlaceForearm's elbow exists for |l1 - l2| <= r <= l1 + l2; the margin keeps
  // in every distance its own rounding could still take in.
  constexpr double kReachMargin = 1e-6;  // m
  return r_min <= l1_ + l2_ + kReachMargin && r_max >= std::abs(l1_ - l2_) - kReachMargin;
}

bool ArmIk::CheckPosition(const Eigen::VectorXd& q, const Eigen::Vector3d& p_b) const {
  return (model_.ForwardKinematics(q).translation() - p_b).norm() <= options_.position_tolerance_m;
}

namespace {

/// Nearest q_seed first; equally near ones keep their order.
void StableSortBySeed(const Eigen::VectorXd& q_seed, std::vector<Eigen::VectorXd>* qs) {
  std::stable_sort(qs->begin(), qs->end(), [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - q_seed).squaredNorm() < (b - q_seed).squaredNorm();
  });
}

}  // namespace

void ArmIk::SortBySeed(const Eigen::VectorXd& q_seed,
                       std::vector<Eigen::VectorXd>* solutions) const {
  StableSortBySeed(q_seed, solutions);
  // Drop duplicates (e.g. a zero elbow discriminant gives the same solution twice).
  auto last = std::unique(solutions->begin(), solutions->end(),
                          [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
                            return (a - b).cwiseAbs().maxCoeff() < 1e-9;
                          });
  solutions->erase(last, solutions->end());
}

void ArmIk::PlaceForearm(const Eigen::Vector3d& p_b,
                         std::vector<ForearmPlacement>* placements) const {
  const Eigen::Vector3d v = p_b - o1_;
  if (!InReach(v.norm(), v.norm())) return;  // no yaw or elbow branch reaches it
  Eigen::Vector3d v_perp = v - v.dot(w_[0]) * w_[0];
  const Eigen::Vector3d h = v_perp.norm() > kGeomTol ? Eigen::Vector3d(v_perp.normalized()) : h0_;
  for (double yaw_sign : {1.0, -1.0}) {
    const double q0 = SignedAngle(h0_, yaw_sign * h, w_[0]);
    if (!Fits(0, q0)) continue;  // every solution on this branch is out of the limits
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
      if (!Fits(1, q1)) continue;
      const Eigen::Vector3d f1 = (p1 - e1).normalized();
      const Eigen::Vector3d f2 = Eigen::AngleAxisd(-q1, w_[1]) * f1;
      const double q2 = SignedAngle(f0_, f2, w_[2]);
      if (!Fits(2, q2)) continue;
      ForearmPlacement placement;
      placement.q[0] = q0;
      placement.q[1] = q1;
      placement.q[2] = q2;
      placement.R012 =
          R0 * Eigen::AngleAxisd(q1, w_[1]).toRotationMatrix() * Eigen::AngleAxisd(q2, w_[2]);
      placements->push_back(placement);
    }
  }
}

void ArmIk::AnalyticPosition(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                             double seed_roll, std::vector<Eigen::VectorXd>* candidates) const {
  std::vector<ForearmPlacement> placements;
  PlaceForearm(p_b, &placements);
  for (const ForearmPlacement& placement : placements) {
    const Eigen::Matrix3d& R012 = placement.R012;
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
      q << WrapPi(placement.q[0]), WrapPi(placement.q[1]), WrapPi(placement.q[2]), rolls[k];
      if (FitLimits(&q)) candidates->push_back(q);
    }
  }
}

namespace {

/// The angle turning u about the unit axis w onto v (their parts normal to w).
double RotationAbout(const Eigen::Vector3d& w, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const Eigen::Vector3d u_n = u - w.dot(u) * w, v_n = v - w.dot(v) * w;
  return std::atan2(w.dot(u_n.cross(v_n)), u_n.dot(v_n));
}

}  // namespace

bool ArmIk::ReachesPose(const Eigen::VectorXd& q, const Eigen::Isometry3d& bMe,
                        Eigen::Isometry3d* bMq) const {
  *bMq = model_.ForwardKinematics(q);
  const PoseError error = ComparePoses(*bMq, bMe);
  return error.translation_m <= options_.position_tolerance_m &&
         error.rotation_rad <= options_.orientation_tolerance_rad;
}

void ArmIk::WristPose(const Eigen::Isometry3d& bMe,
                      std::vector<Eigen::VectorXd>* candidates) const {
  const Eigen::Matrix3d& Re = bMe.linear();
  const Eigen::Vector3d centre = bMe.translation() - Re * d_e_;
  std::vector<ForearmPlacement> placements;
  PlaceForearm(centre, &placements);
  const Eigen::Vector3d &w3 = w_[3], &w4 = w_[4], &w5 = w_[5];
  const double c34 = w3.dot(w4);
  const Eigen::Vector3d w34 = w3.cross(w4);
  const Eigen::Vector3d x5 = AnyPerpendicular(w5);
  for (const ForearmPlacement& placement : placements) {
    // exp(w3 q3) exp(w4 q4) exp(w5 q5) = M: two rotations about intersecting
    // axes take w5 onto M w5 (Paden-Kahan subproblem 2), the last turns about w5.
    const Eigen::Matrix3d M = placement.R012.transpose() * Re * Re0_.transpose();
    const Eigen::Vector3d v = M * w5;
    const double den = c34 * c34 - 1.0;
    const double alpha = (c34 * w4.dot(w5) - w3.dot(v)) / den;
    const double beta = (c34 * w3.dot(v) - w4.dot(w5)) / den;
    const double gamma_sq =
        (1.0 - alpha * alpha - beta * beta - 2.0 * alpha * beta * c34) / w34.squaredNorm();
    if (gamma_sq < -1e-9) continue;
    const double gamma = std::sqrt(std::max(0.0, gamma_sq));
    for (double sign : {1.0, -1.0}) {
      if (sign < 0.0 && gamma == 0.0) break;
      const Eigen::Vector3d z = alpha * w3 + beta * w4 + sign * gamma * w34;
      const double q3 = RotationAbout(w3, z, v);
      if (!Fits(3, q3)) continue;
      const double q4 = RotationAbout(w4, w5, z);
      if (!Fits(4, q4)) continue;
      const Eigen::Matrix3d R34 =
          Eigen::AngleAxisd(q3, w3).toRotationMatrix() * Eigen::AngleAxisd(q4, w4);
      const double q5 = RotationAbout(w5, x5, R34.transpose() * M * x5);
      Eigen::VectorXd q(6);
      q << WrapPi(placement.q[0]), WrapPi(placement.q[1]), WrapPi(placement.q[2]), WrapPi(q3),
          WrapPi(q4), WrapPi(q5);
      if (FitLimits(&q)) candidates->push_back(q);
    }
  }
}

template <typename Check>
int ArmIk::KeepChecked(const Eigen::VectorXd& q_seed, bool nearest_only, const Check& check,
                       std::vector<Eigen::VectorXd>* candidates) const {
  if (!nearest_only) {
    candidates->erase(std::remove_if(candidates->begin(), candidates->end(),
                                     [&check](const Eigen::VectorXd& q) { return !check(q); }),
                      candidates->end());
    SortBySeed(q_seed, candidates);
    return static_cast<int>(candidates->size());
  }
  // Sorting before or after dropping the failed ones gives the passing ones
  // the same order (the sort is stable): the first that passes is the first
  // of the full list.
  StableSortBySeed(q_seed, candidates);
  for (Eigen::VectorXd& q : *candidates) {
    if (!check(q)) continue;
    Eigen::VectorXd nearest = std::move(q);
    candidates->assign(1, std::move(nearest));
    return 1;
  }
  candidates->clear();
  return 0;
}

int ArmIk::Pose(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                bool nearest_only, std::vector<Eigen::VectorXd>* solutions) const {
  assert(q_seed.size() == model_.dof());
  solutions->clear();
  if (!bMe_target.matrix().allFinite()) return 0;
  if (kind_ == Kind::kSphericalWrist) {
    WristPose(bMe_target, solutions);
    return KeepChecked(
        q_seed, nearest_only,
        [&](const Eigen::VectorXd& q) {
          Eigen::Isometry3d reached;
          return ReachesPose(q, bMe_target, &reached);
        },
        solutions);
  }
  Eigen::VectorXd q;
  if (SolvePoseNumeric(bMe_target, q_seed, &q)) solutions->push_back(q);
  return static_cast<int>(solutions->size());
}

int ArmIk::SolvePose(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                     std::vector<Eigen::VectorXd>* solutions) const {
  return Pose(bMe_target, q_seed, false, solutions);
}

bool ArmIk::SolvePoseNearest(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                             Eigen::VectorXd* q) const {
  std::vector<Eigen::VectorXd> solutions;
  if (Pose(bMe_target, q_seed, true, &solutions) == 0) return false;
  *q = std::move(solutions.front());
  return true;
}

int ArmIk::SolvePosition(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                         const Eigen::VectorXd& q_seed,
                         std::vector<Eigen::VectorXd>* solutions) const {
  return Position(p_b, x_b, q_seed, false, solutions);
}

bool ArmIk::SolvePositionNearest(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                                 const Eigen::VectorXd& q_seed, Eigen::VectorXd* q) const {
  std::vector<Eigen::VectorXd> solutions;
  if (Position(p_b, x_b, q_seed, true, &solutions) == 0) return false;
  *q = std::move(solutions.front());
  return true;
}

int ArmIk::Position(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                    const Eigen::VectorXd& q_seed, bool nearest_only,
                    std::vector<Eigen::VectorXd>* solutions) const {
  assert(q_seed.size() == model_.dof());
  solutions->clear();
  if (!p_b.allFinite() || !x_b.allFinite()) return 0;
  if (kind_ == Kind::kYawPitchPitchRoll) {
    AnalyticPosition(p_b, x_b, q_seed[3], solutions);
    return KeepChecked(
        q_seed, nearest_only, [&](const Eigen::VectorXd& q) { return CheckPosition(q, p_b); },
        solutions);
  }
  if (kind_ == Kind::kSphericalWrist) {
    // The seed's approach axis, the closing axis x_b turned normal to it.
    const Eigen::Isometry3d bMs = model_.ForwardKinematics(q_seed);
    const Eigen::Vector3d z = bMs.linear().col(2);
    const Eigen::Vector3d x_perp = x_b - x_b.dot(z) * z;
    const Eigen::Vector3d x =
        x_perp.norm() > 1e-9 ? Eigen::Vector3d(x_perp.normalized()) : bMs.linear().col(0);
    Eigen::Isometry3d bMe = Eigen::Isometry3d::Identity();
    bMe.linear().col(0) = x;
    bMe.linear().col(1) = z.cross(x);
    bMe.linear().col(2) = z;
    bMe.translation() = p_b;
    return Pose(bMe, q_seed, nearest_only, solutions);
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

int ArmIk::SolveClosedForm(const Eigen::Isometry3d& bMe, const Eigen::VectorXd& q_seed,
                           std::vector<Eigen::VectorXd>* solutions) const {
  solutions->clear();
  switch (kind_) {
    case Kind::kSphericalWrist:
      return SolvePose(bMe, q_seed, solutions);
    case Kind::kYawPitchPitchRoll:
      return SolvePosition(bMe.translation(), bMe.linear().col(0), q_seed, solutions);
    case Kind::kNumeric:
      break;
  }
  return 0;
}

int ArmIk::GraspAxisDepths() const { return std::max(1, options_.depth_samples); }

double ArmIk::GraspAxisDepth(int i, double depth_min_m, double depth_max_m) const {
  const int n = GraspAxisDepths();
  if (n == 1) return 0.5 * (depth_min_m + depth_max_m);
  return depth_min_m + (depth_max_m - depth_min_m) * i / static_cast<double>(n - 1);
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
  auto add = [&](const Eigen::VectorXd& q, double depth, const Eigen::Isometry3d& bMe) {
    GraspAxisSolution s;
    s.q = q;
    s.bMe = bMe;
    s.depth_m = depth;
    solutions->push_back(std::move(s));
  };

  if (kind_ == Kind::kYawPitchPitchRoll) {
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
      const Eigen::Vector3d p_b = c_b + depth * a;
      AnalyticPosition(p_b, x, q_seed[3], &qs);
      for (const Eigen::VectorXd& q : qs) {
        const Eigen::Isometry3d bMe = model_.ForwardKinematics(q);
        if ((bMe.translation() - p_b).norm() > options_.position_tolerance_m) continue;
        // Keep the branches whose approach is the one solved for (the other
        // elbow branch reaches the same point with another approach).
        if (bMe.linear().col(2).dot(a) > std::cos(options_.orientation_tolerance_rad)) {
          add(q, depth, bMe);
        }
      }
      qs.clear();
    }
  } else if (kind_ == Kind::kSphericalWrist) {
    // SolvePose's nearest solution per closing sign, checked against the
    // forward kinematics nearest first until one passes.
    const Eigen::Vector3d e1 = AnyPerpendicular(x), e2 = x.cross(e1);
    const int n = std::max(1, options_.approach_samples);
    // The wrist centre of the tool pose at `depth` and closing sign s lies on a
    // circle about the contact centre, normal to x: -s d_x along x, at
    // hypot(depth - d_z, d_y) from it across. A closing sign whose circle keeps
    // out of the forearm's reach has no solution at any approach angle.
    const Eigen::Vector3d v = c_b - o1_;
    const double v_along = v.dot(x), v_across = (v - v_along * x).norm();
    const auto circle_in_reach = [&](double depth, double s) {
      const double along = v_along - s * d_e_.x();
      const double radius = std::hypot(depth - d_e_.z(), d_e_.y());
      return InReach(std::hypot(along, v_across - radius), std::hypot(along, v_across + radius));
    };
    std::vector<Eigen::VectorXd> qs;
    for (int k = 0; k < n * GraspAxisDepths(); ++k) {
      const double depth = GraspAxisDepth(k / n, depth_min_m, depth_max_m);
      if (!circle_in_reach(depth, 1.0) && !circle_in_reach(depth, -1.0)) continue;
      const double phi = 2.0 * kPi * (k % n) / n;
      const Eigen::Vector3d a = std::cos(phi) * e1 + std::sin(phi) * e2;
      // The fingers are symmetric: closing along -x is as good; the solution
      // nearest the seed of either.
      bool found = false;
      Eigen::VectorXd best;
      Eigen::Isometry3d best_bMe;
      for (double s : {1.0, -1.0}) {
        if (!circle_in_reach(depth, s)) continue;
        Eigen::Isometry3d bMe = Eigen::Isometry3d::Identity();
        bMe.linear().col(0) = s * x;
        bMe.linear().col(1) = a.cross(s * x);
        bMe.linear().col(2) = a;
        bMe.translation() = c_b + depth * a;
        qs.clear();
        WristPose(bMe, &qs);
        Eigen::Isometry3d reached;
        const auto reaches = [&](const Eigen::VectorXd& q) {
          return ReachesPose(q, bMe, &reached);
        };
        if (KeepChecked(q_seed, true, reaches, &qs) == 0) continue;
        if (!found || (qs.front() - q_seed).squaredNorm() < (best - q_seed).squaredNorm()) {
          best = qs.front();
          best_bMe = reached;
          found = true;
        }
      }
      if (found) add(best, depth, best_bMe);
    }
  } else {
    // Numeric: one solve per approach angle is costly enough; closing along
    // -x only when +x has none.
    const Eigen::Vector3d e1 = AnyPerpendicular(x), e2 = x.cross(e1);
    const int n = std::max(1, options_.approach_samples);
    Eigen::VectorXd q;
    for (int k = 0; k < n * GraspAxisDepths(); ++k) {
      const double depth = GraspAxisDepth(k / n, depth_min_m, depth_max_m);
      const double phi = 2.0 * kPi * (k % n) / n;
      const Eigen::Vector3d a = std::cos(phi) * e1 + std::sin(phi) * e2;
      for (double s : {1.0, -1.0}) {
        Eigen::Isometry3d bMe = Eigen::Isometry3d::Identity();
        bMe.linear().col(0) = s * x;
        bMe.linear().col(1) = a.cross(s * x);
        bMe.linear().col(2) = a;
        bMe.translation() = c_b + depth * a;
        if (!SolvePoseNumeric(bMe, q_seed, &q)) continue;
        add(q, depth, model_.ForwardKinematics(q));
        break;
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
