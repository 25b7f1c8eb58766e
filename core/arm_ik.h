// Inverse kinematics of the arms: closed form for the yaw-pitch-pitch-roll
// chain of the 4-DoF arms and for the yaw-pitch-pitch chain with a spherical
// wrist of the 6-DoF arms, damped Gauss-Newton for any other chain. Frames:
// everything is in the arm base b (bl or br); the tool frame e has z along the
// approach and x along the fingers' closing direction (core/frames.h). Units
// m and rad. The solver is a description (built once from an ArmModel); the
// queries are const, keep no state and may run concurrently.
//
// What a 4-DoF arm can reach: the shoulder yaw turns a vertical plane, the two
// pitches place the elbow and the tool in that plane, and the roll turns the
// gripper about the forearm, which is the approach axis. So the tool position
// fixes the approach (up to the elbow and yaw branches) and only the rotation
// about the approach is free: a target "position + approach" is reachable only
// when the approach line meets the yaw axis. SolveGraspAxis uses the freedoms
// a two-finger grasp has (the approach may turn about the closing axis, and the
// contacts may sit anywhere along the finger pads) to meet that condition exactly.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "core/arm_model.h"

namespace aerograsp {

/// Settings of the numeric solver (chains without a closed form) and the
/// acceptance tolerances of every solution.
struct IkOptions {
  double position_tolerance_m{1e-5};       ///< FK check of each solution, (0, 0.01] m
  double orientation_tolerance_rad{1e-4};  ///< FK check of each solution, (0, 0.1] rad
  int max_iterations{60};                  ///< numeric solver iterations per seed, [1, 1000]
  double damping{0.005};                   ///< numeric solver damping lambda, [0, 1]
  /// SolveGraspAxis without the 4-DoF closed form: approach angles about the
  /// closing axis, [1, 64] ...
  int approach_samples{8};
  /// ... and depths along the pads, evenly from depth_min_m to depth_max_m
  /// (1: the middle only), [1, 16]. A few of each let the 6-DoF arm take the
  /// grasps that only a slanted approach or a deeper or shallower hold reaches.
  int depth_samples{1};
};

/// One grasp-axis solution: joints, the tool pose, and where the contacts sit.
struct GraspAxisSolution {
  Eigen::VectorXd q;      ///< joint positions (rad), within limits
  Eigen::Isometry3d bMe;  ///< tool pose they give (FK)
  double depth_m = 0.0;   ///< tool point beyond the contact centre along the approach (m)
};

class ArmIk {
 public:
  /// Copies the model and analyses its chain. A closed form is used when the
  /// chain starts with three revolute joints, j0 a yaw whose axis passes
  /// through j1's origin, j1 and j2 parallel and perpendicular to j0, and the
  /// forearm (from j2's origin) in the plane of j1's origin normal to j1, and
  /// then either
  /// - four joints: j3 along the forearm line, the tool point on that line with
  ///   its z axis along it (the shipped 4-DoF arm), or
  /// - six joints: j3, j4, j5 revolute with axes through one point, the wrist
  ///   centre, at the forearm's end (the shipped 6-DoF arm).
  /// Otherwise the numeric solver is used.
  explicit ArmIk(const ArmModel& model, const IkOptions& options = {});

  const ArmModel& model() const { return model_; }
  /// True when a closed form applies (see the constructor).
  bool is_analytic() const { return kind_ != Kind::kNumeric; }
  /// True when SolveClosedForm gives every joint vector within the limits that
  /// reaches a full tool pose (the spherical-wrist chain): a numeric search
  /// from other seeds can find no other.
  bool closed_form_solves_pose() const { return kind_ == Kind::kSphericalWrist; }

  /// Position IK: every solution within the joint limits that puts the tool
  /// point at p_b, sorted by distance to q_seed (size dof()). The rotation about
  /// the approach is chosen so that the closing axis x_e is as close as possible
  /// to +-x_b (x_b need not be perpendicular to the approach; a zero x_b keeps
  /// the seed's roll). Closed form: up to 8 solutions (yaw, elbow and roll
  /// branches). Spherical wrist: the pose with the seed's approach axis and
  /// the closing axis x_b turned normal to it (up to 8). Numeric: at most one
  /// (from the seed, position only).
  /// Returns the number of solutions written to `solutions` (cleared first).
  int SolvePosition(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                    const Eigen::VectorXd& q_seed, std::vector<Eigen::VectorXd>* solutions) const;

  /// Full pose IK from q_seed by damped Gauss-Newton (any chain, any dof).
  /// Returns true and writes q when the pose is reached within the tolerances
  /// and the joint limits.
  bool SolvePoseNumeric(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                        Eigen::VectorXd* q) const;

  /// Full pose IK: every solution within the joint limits that reaches
  /// bMe_target within the tolerances, sorted by distance to q_seed. Closed
  /// form for the spherical-wrist chain (up to 8: yaw, elbow and wrist
  /// branches); otherwise SolvePoseNumeric from q_seed (at most one).
  /// Returns the number written to `solutions` (cleared first).
  int SolvePose(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                std::vector<Eigen::VectorXd>* solutions) const;

  /// The first solution SolvePose lists (the one nearest q_seed), without
  /// checking the others against the forward kinematics. Returns false when
  /// SolvePose finds none.
  bool SolvePoseNearest(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed,
                        Eigen::VectorXd* q) const;

  /// The first solution SolvePosition lists (the one nearest q_seed), the
  /// same way. Returns false when SolvePosition finds none.
  bool SolvePositionNearest(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
                            const Eigen::VectorXd& q_seed, Eigen::VectorXd* q) const;

  /// What the closed form gives for a tool pose bMe (none without one), sorted
  /// by distance to q_seed: the spherical-wrist chain's full pose solutions
  /// (SolvePose); the 4-DoF chain's solutions for the tool point with the
  /// closing axis x_e (SolvePosition: its approach follows from the position).
  /// Returns the number written to `solutions` (cleared first).
  int SolveClosedForm(const Eigen::Isometry3d& bMe, const Eigen::VectorXd& q_seed,
                      std::vector<Eigen::VectorXd>* solutions) const;

  /// How far q keeps from where the spherical-wrist chain loses a freedom
  /// (rad): the least of its wrist joints' (j3, j4, j5) distances to their
  /// limits and of the middle one's (j4) distance to 0 and +-pi, where the two
  /// rolls turn about one axis and a small turn of the tool takes a large one
  /// of theirs. Infinity for the other chains (the 4-DoF arm's solutions
  /// differ by branch, not along a wrist).
  double WristMargin(const Eigen::VectorXd& q) const;

  /// Grasp-axis IK: the fingers close along +-x_b (unit) through the contact
  /// centre c_b, the approach z_e is any direction perpendicular to x_b, and the
  /// tool point is at c_b + depth * z_e with depth in [depth_min_m, depth_max_m]
  /// (where the contacts sit along the pads). Closed form for the 4-DoF chain
  /// (exact: the approach and depth that meet the yaw-plane condition);
  /// otherwise SolvePose at `approach_samples` approach angles, both closing
  /// signs, and `depth_samples` depths, keeping per approach angle and depth
  /// the solution nearest q_seed. Solutions are sorted by distance to q_seed.
  /// Returns the number written to `solutions` (cleared first).
  int SolveGraspAxis(const Eigen::Vector3d& c_b, const Eigen::Vector3d& x_b, double depth_min_m,
                     double depth_max_m, const Eigen::VectorXd& q_seed,
                     std::vector<GraspAxisSolution>* solutions) const;

 private:
  enum class Kind { kNumeric, kYawPitchPitchRoll, kSphericalWrist };
  /// The yaw and the two pitches that put the forearm's end (the 4-DoF arm's
  /// tool point, the 6-DoF arm's wrist centre) at p_b.
  struct ForearmPlacement {
    double q[3];
    Eigen::Matrix3d R012;  ///< their rotation
  };
  void AnalyseChain();
  /// Yaw, then elbow branches, those whose three joints fit their limits
  /// (Fits); appends to `placements`.
  void PlaceForearm(const Eigen::Vector3d& p_b, std::vector<ForearmPlacement>* placements) const;
  /// Closed-form position IK: the joint vectors within the limits, not yet
  /// checked against the forward kinematics (CheckPosition), no sorting;
  /// appends to `candidates`.
  void AnalyticPosition(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b, double seed_roll,
                        std::vector<Eigen::VectorXd>* candidates) const;
  /// Closed-form pose IK of the spherical-wrist chain: the joint vectors within
  /// the limits, not yet checked (ReachesPose), no sorting; appends.
  void WristPose(const Eigen::Isometry3d& bMe, std::vector<Eigen::VectorXd>* candidates) const;
  /// The forward kinematics of q (written to bMq) reach bMe within the tolerances.
  bool ReachesPose(const Eigen::VectorXd& q, const Eigen::Isometry3d& bMe,
                   Eigen::Isometry3d* bMq) const;
  /// The closed-form candidates (AnalyticPosition or WristPose) that pass
  /// `check`: all of them sorted by distance to q_seed (nearest_only false),
  /// else only the nearest, checking them nearest first until one passes.
  /// Either way the first is the same.
  template <typename Check>
  int KeepChecked(const Eigen::VectorXd& q_seed, bool nearest_only, const Check& check,
                  std::vector<Eigen::VectorXd>* candidates) const;
  int Pose(const Eigen::Isometry3d& bMe_target, const Eigen::VectorXd& q_seed, bool nearest_only,
           std::vector<Eigen::VectorXd>* solutions) const;
  int Position(const Eigen::Vector3d& p_b, const Eigen::Vector3d& x_b,
               const Eigen::VectorXd& q_seed, bool nearest_only,
               std::vector<Eigen::VectorXd>* solutions) const;
  /// Wraps each joint angle into its limits (+-2 pi) when possible.
  bool FitLimits(Eigen::VectorXd* q) const;
  /// FitLimits for joint i alone.
  bool FitLimit(int i, double* v) const;
  /// Whether joint i's angle, wrapped into (-pi, pi], passes FitLimit: the
  /// closed forms leave a branch early when one of its joints cannot.
  bool Fits(int i, double angle) const;
  bool CheckPosition(const Eigen::VectorXd& q, const Eigen::Vector3d& p_b) const;
  /// Whether the forearm's end can be at some distance in [r_min, r_max] (m)
  /// from the shoulder (o1_): false only where PlaceForearm finds no placement
  /// (a margin above rounding).
  bool InReach(double r_min, double r_max) const;
  /// The sampled grasp-axis depths (IkOptions::depth_samples, at least 1) and
  /// the i-th of them: evenly from depth_min_m to depth_max_m, the middle for one.
  int GraspAxisDepths() const;
  double GraspAxisDepth(int i, double depth_min_m, double depth_max_m) const;
  void SortBySeed(const Eigen::VectorXd& q_seed, std::vector<Eigen::VectorXd>* solutions) const;

  ArmModel model_;
  IkOptions options_;
  Kind kind_ = Kind::kNumeric;
  // Closed-form chain description, base frame, at q = 0. The forearm's end is
  // the tool point (4-DoF) or the wrist centre (6-DoF).
  Eigen::Vector3d w_[6];        // joint axes (unit)
  Eigen::Vector3d o1_;          // shoulder pitch origin (on the yaw axis)
  Eigen::Vector3d h0_;          // in-plane horizontal direction at q = 0: unit(w1 x w0)
  Eigen::Vector3d u0_;          // upper arm direction at q = 0: unit(o2 - o1)
  Eigen::Vector3d f0_;          // forearm direction at q = 0: unit(end - o2)
  Eigen::Vector3d xe0_;         // tool x axis at q = 0
  double l1_ = 0.0;             // |o2 - o1|
  double l2_ = 0.0;             // |end - o2|
  double approach_sign_ = 1.0;  // 4-DoF: z_e = approach_sign_ * forearm direction
  Eigen::Matrix3d Re0_ = Eigen::Matrix3d::Identity();  // 6-DoF: tool rotation at q = 0
  Eigen::Vector3d d_e_ = Eigen::Vector3d::Zero();  // 6-DoF: tool point from the wrist centre, in e
};

}  // namespace aerograsp
