// Dual-arm grasp planning (paper Sect. 4): per-arm feasibility of every
// contact pair (grasp-axis IK with joint limits, pre-catch pose, collisions of
// the arm and its open fingers with the object, the safe volume and the other
// arm), dual pairs ranked by quality and by cost from the current arm state.
// Which pair to follow and when to switch is the grasp policy's
// (mission/grasp_policy.h), over these rankings.
//
// Frames: d body (FRD), b arm base, o object, g grasp (= tool frame e at the
// grasp: z approach, x closing). Units m, rad. The planner is an immutable
// description built once per object; Plan is const, keeps no state but a
// cache of exact qualities (behind a mutex) and may run concurrently (the
// mission re-plans in its own thread).
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/arm_ik.h"
#include "core/platform.h"
#include "grasp/contacts.h"
#include "grasp/quality.h"

namespace aerograsp {

class PlatformCollision;

struct GraspPlannerConfig {
  ContactOptions contacts;
  FrictionConfig friction;
  /// contacts at least this far behind the tool point along the approach, [-0.02, 0.2] m (the tool
  /// point is 0.02 m inside the tips)
  double depth_min_m{0.0};
  double depth_max_m{0.08};  ///< and at most this far (on the pads), (depth_min_m, finger_length_m)
  double precatch_distance_m{0.08};  ///< pre-catch tool point back along the approach, [0, 0.3] m
  /// Arm clearance to the safe volume, [0, 0.1] m. Default 0 (touching counts):
  /// the volume's lower face is only 0.03 m above the shoulder pitch axes and the
  /// upper arm's box sweeps to 0.005 m of it as it turns, so any larger margin
  /// would forbid most of the workspace; the volume itself is the margin.
  double safe_volume_margin_m{0.0};
  double arms_margin_m{0.01};   ///< clearance between the two arms, [0, 0.1] m
  double object_margin_m{0.0};  ///< arm and open fingers to the object, [0, 0.05] m
  int support_directions{256};  ///< directions of the fast epsilon bound, [12, 4096]
  int exact_top_k{20};          ///< best pairs whose epsilon is recomputed exactly, [0, 10000]
  double quality_weight{1.0};   ///< score per unit of epsilon, [0, 100]
  double task_weight{0.05};     ///< score per unit of the weight-share term, [0, 100]
  double cost_weight_per_rad{0.005};  ///< score lost per rad of joint travel (both arms), [0, 10]
  /// A pair counts as robust for an arm when it stays feasible with the object
  /// moved this far along +-x, +-y and +-z of d (the sway and the vehicle's
  /// tracking error move it so while the arms servo); robust dual grasps rank
  /// first. [0, 0.1] m; 0 makes every feasible pair robust.
  double reach_margin_m{0.0};
  /// ... and on the same IK branch: with the object moved, the arm's solution
  /// nearest the unmoved one differs from it by at most this much in every
  /// joint (the mission follows a pair only on the branch it was planned on;
  /// a 6-DoF grasp with a wrist joint near its limit is feasible through the
  /// sway only on other branches). [0, 6.3] rad; 0: any branch counts.
  double robust_branch_rad{0.0};
  /// Plan tries first, for each pair, the arm's grasp-axis solutions whose
  /// wrist keeps this far from its singularity and its limits
  /// (ArmIk::WristMargin: the 6-DoF arm), nearest the current joints among
  /// them, then the others: a grasp on the wrist's singularity or at a wrist
  /// limit leaves the followed branch with a centimetre of sway. [0, 1.5]
  /// rad; 0: nearest the current joints only. A grasp without the margin
  /// does not count as robust.
  double wrist_margin_rad{0.0};
  /// A pair counts as clear of edges when its contacts stay on their faces
  /// with the object shifted this far along them (ContactsClearOfEdges): a
  /// pose estimate off by as much still puts the pads on the object. Dual
  /// grasps clear of edges rank first (after robust ones). [0, 0.05] m; 0
  /// makes every pair clear.
  double edge_margin_m{0.0};
  /// The grasp-axis IK of an arm without the 4-DoF closed form (the 6-DoF
  /// arm; IkOptions): approach angles about the closing axis, [1, 64], and
  /// depths along the pads, [1, 16], tried for each pair.
  int grasp_axis_approaches{8};
  int grasp_axis_depths{1};

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><key>: ..." naming the
  /// bound; depth_max_m at most kLongestFingerM here, CheckFingers checks it
  /// against the platform's gripper.
  void Validate(const std::string& source, const std::string& prefix) const;
  /// @throws ConfigError "<source>: <prefix>depth_max_m: ..." when the
  /// contacts lie deeper than `gripper`'s fingers reach.
  void CheckFingers(const GripperConfig& gripper, const std::string& source,
                    const std::string& prefix) const;
};

/// The object as the planner needs it (from data/objects/NAME/object.yaml or a
/// bare mesh, whose centre of mass is then computed at uniform density).
/// Not named ObjectModel: core/object_model.h has that name, and two classes of
/// one name in one program break the one-definition rule (the linker keeps one
/// inline destructor for both, which corrupts the heap).
struct GraspObject {
  std::string name;
  TriangleMesh mesh_o;  ///< closed, metres, frame o
  double mass_kg = 0.0;
  Eigen::Vector3d com_o = Eigen::Vector3d::Zero();  ///< centre of mass in o
};

/// One arm's feasible grasp of one contact pair.
struct ArmGrasp {
  int pair = -1;  ///< index into contacts().pairs
  Side side = Side::kLeft;
  Eigen::VectorXd q_grasp;                                ///< rad
  Eigen::VectorXd q_precatch;                             ///< rad
  Eigen::Isometry3d dMg = Eigen::Isometry3d::Identity();  ///< tool at the grasp, in d
  Eigen::Isometry3d dMp = Eigen::Isometry3d::Identity();  ///< tool at the pre-catch, in d
  double depth_m = 0.0;        ///< contacts this far behind the tool point
  double cost_rad = 0.0;       ///< |q_grasp - q_current|
  bool robust = true;          ///< feasible too with the object moved by reach_margin_m (Plan)
  bool clear_of_edges = true;  ///< contacts edge_margin_m or more from their faces' edges
};

/// Why an arm cannot take a contact pair (the first test that failed on its
/// most promising IK solution).
enum class Infeasibility {
  kNone,
  kUnreachable,          ///< no IK solution within the joint limits
  kSafeVolume,           ///< every solution enters the safe volume
  kObjectCollision,      ///< the arm or open fingers hit the object at the grasp
  kPrecatchUnreachable,  ///< the pre-catch point has no IK solution
  kPrecatchCollision,    ///< the pre-catch pose hits the object or the safe volume
};
const char* InfeasibilityName(Infeasibility why);

struct ArmStats {
  int candidates = 0;
  int feasible = 0;
  int by_reason[6] = {0, 0, 0, 0, 0, 0};  ///< counts per Infeasibility (index = enum value)
  double seconds = 0.0;
};
/// The infeasible pairs by reason, "80 unreachable, 20 hits the object" ("" when none).
std::string DescribeReasons(const ArmStats& stats);

/// A ranked dual grasp.
struct DualGrasp {
  ArmGrasp left, right;
  double epsilon = 0.0;        ///< Ferrari-Canny epsilon of both grippers' contacts together
  bool epsilon_exact = false;  ///< true: Qhull; false: the support-function upper bound
  double task = 0.0;           ///< weight-share term [0, 1]
  double left_share = 0.0;     ///< fraction of the weight on the left arm
  double score = 0.0;          ///< quality_weight eps + task_weight task - cost_weight cost
  bool robust = true;          ///< both arm grasps are robust (ArmGrasp::robust)
  bool clear_of_edges = true;  ///< both arm grasps are (ArmGrasp::clear_of_edges)
};

struct PairStats {
  long long considered = 0;        ///< feasible left x feasible right, different pairs
  long long no_force_closure = 0;  ///< bound <= 0
  long long arms_collide = 0;      ///< the two arms touch at the grasp or pre-catch
  long long exact_dropped = 0;     ///< bound > 0 but no force closure in the exact hull
  long long valid = 0;             ///< ranked
  double quality_seconds = 0.0;    ///< bound + task term over `considered`
  double exact_seconds = 0.0;      ///< Qhull over `exact_evaluations`
  int exact_evaluations = 0;
  double collision_seconds = 0.0;
};

/// What a plan is asked: where the object is and where the arms are now.
struct PlanQuery {
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();  ///< object in the body frame
  Eigen::VectorXd q_left, q_right;                        ///< current joints (rad)
  Eigen::Vector3d gravity_d = Eigen::Vector3d::UnitZ();   ///< gravity direction in d (FRD, level)
};

struct PlanResult {
  std::vector<ArmGrasp> left, right;  ///< feasible per arm, in contact-pair order
  ArmStats left_stats, right_stats;
  std::vector<DualGrasp> ranked;  ///< valid pairs, best first
  PairStats pair_stats;
};

class GraspPlanner {
 public:
  /// Copies what it needs from `platform`. Precomputes, per contact pair, its wrenches (torques
  /// about the centre of mass divided by the object's largest vertex distance from it) and their
  /// support table, and builds the object's collision model.
  /// @throws ConfigError from config.Validate; std::invalid_argument when the
  /// platform's arms have different joint counts or the mesh is empty.
  GraspPlanner(const Platform& platform, GraspObject object, ContactSet contacts,
               const GraspPlannerConfig& config);
  ~GraspPlanner();
  GraspPlanner(const GraspPlanner&) = delete;
  GraspPlanner& operator=(const GraspPlanner&) = delete;

  const ContactSet& contacts() const { return contacts_; }
  const GraspObject& object() const { return object_; }
  const GraspPlannerConfig& config() const { return config_; }
  double torque_scale_m() const { return torque_scale_m_; }

  /// Feasibility of one contact pair for one arm with the object at dMo, IK
  /// seeded (and solutions ordered) by q_current. Returns true and fills `out`.
  bool EvaluateArm(Side side, int pair, const Eigen::Isometry3d& dMo,
                   const Eigen::VectorXd& q_current, ArmGrasp* out, Infeasibility* why) const;
  /// EvaluateArm with the solutions keeping wrist_margin_rad tried first (Plan's order).
  bool EvaluateArmWithMargin(Side side, int pair, const Eigen::Isometry3d& dMo,
                             const Eigen::VectorXd& q_current, ArmGrasp* out,
                             Infeasibility* why) const;

  /// Every pair for both arms (with its robustness, see reach_margin_m), then
  /// every left x right combination: bound, task term and cost, arms
  /// collision, exact epsilon for the top `exact_top_k` (ranked by it among
  /// themselves; the rest follow by bound). Robust dual grasps come first,
  /// and among each, those clear of edges.
  PlanResult Plan(const PlanQuery& query) const;

  /// What a re-evaluation reads of Plan (the grasp policy's DecideSwitch), at
  /// a fraction of its cost: `ranked` holds Plan's first entry, then the entry
  /// of the kept pair (left_pair, right_pair) when Plan ranks it elsewhere,
  /// each exactly as Plan gives it; the stats of both arms as Plan's. Every
  /// pair's IK and collisions are solved as in Plan, but robustness, the two
  /// arms' clearance and the exact epsilon only for the candidates Plan's
  /// order reaches before both entries are known. `left` and `right` are
  /// empty, `pair_stats` counts what was computed.
  PlanResult PlanFront(const PlanQuery& query, int left_pair, int right_pair) const;

  /// Exact wrench-hull quality of one pair alone (a single grasp) or of two
  /// pairs together (a dual grasp; pass -1 as `other` for a single one).
  WrenchQuality ExactQuality(int pair, int other = -1) const;

 private:
  Eigen::Isometry3d dMb_[2];
  GraspObject object_;
  ContactSet contacts_;
  GraspPlannerConfig config_;
  double torque_scale_m_ = 1.0;
  std::unique_ptr<PlatformCollision> collision_;
  int mesh_handle_ = -1;
  /// Every pair for both arms into result->left, right and their stats;
  /// `robust`: each feasible grasp's robustness too (else left unset).
  void EvaluateArms(const PlanQuery& query, bool robust, PlanResult* result) const;
  /// Every left x right combination of `arms` with force closure by the
  /// bound, scored, sorted by score (the arms' clearance not checked yet).
  std::vector<DualGrasp> Combine(const PlanQuery& query, const PlanResult& arms,
                                 PairStats* ps) const;
  /// The two arms clear each other at the grasp and at the pre-catch.
  bool ArmsClear(const DualGrasp& d) const;
  /// The exact epsilon `q` replaces the bound in d's epsilon and score.
  void SetExactEpsilon(const WrenchQuality& q, DualGrasp* d) const;
  bool Evaluate(Side side, int pair, const Eigen::Isometry3d& dMo, const Eigen::VectorXd& q_current,
                bool margin_first, ArmGrasp* out, Infeasibility* why) const;
  /// True when the arm's grasp `g` keeps wrist_margin_rad and stays feasible
  /// with the object moved by reach_margin_m along each axis of d (on g's
  /// branch: robust_branch_rad).
  bool Robust(Side side, const ArmGrasp& g, const Eigen::Isometry3d& dMo,
              const Eigen::VectorXd& q) const;

  ArmIk ik_[2];
  std::vector<std::vector<Wrench>> wrenches_;  // per pair
  std::vector<float> support_;                 // per pair, support_directions floats
  std::vector<bool> clear_of_edges_;           // per pair (edge_margin_m)
  int directions_ = 0;
  /// ExactQuality by (pair, other): a function of the two pairs alone, asked
  /// for the same few pairs at every re-evaluation (a convex hull each).
  mutable std::mutex quality_mutex_;
  mutable std::map<std::pair<int, int>, WrenchQuality> quality_cache_;
};

}  // namespace aerograsp
