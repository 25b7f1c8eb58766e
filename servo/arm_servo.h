// One arm's servo loop: PBVS twist (servo/pbvs.h) -> prioritized damped least
// squares (position first, then orientation) -> joint-limit avoidance, speed
// and acceleration limits -> safe-volume check -> joint targets. Bad input never
// throws out of Step(): it returns a hold status with a zero velocity.
//
// Far from the target a purely Cartesian law falls into local minima: the
// shoulder yaw runs into its limit when the straight tool path passes near the
// yaw axis, the elbow stops at its limit, and a 4-DoF arm has no joint left to
// turn its approach axis once the position is met (that axis is set by the
// branch the position is reached in). So each target is first solved by the
// damped least-squares IK (servo/ik.h, same task priorities) for a joint goal
// q* whose straight joint path is allowed by the forbidden predicate; far from
// q* the servo moves along that path (joint limits are a box, so a straight
// joint path never leaves them), near it the PBVS law takes over and tracks the
// target as vision updates it. q* follows a moving target by warm-started IK.
// The search for a new q* starts from the arm's closed-form solutions of the
// target and is spread over Steps: at most search_budget IK iterations and
// collision checks each, so no Step takes much longer than the others.
// Two arms that hold each other up share a RightOfWay (servo/right_of_way.h):
// the one farther from its target backs off to a via configuration.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/arm_model.h"
#include "servo/dls.h"
#include "servo/ik.h"
#include "servo/pbvs.h"
#include "servo/right_of_way.h"

namespace aerograsp {

struct ServoConfig {
  double gain_per_s{3.0};           ///< PBVS error decrease rate lambda, (0, 50] 1/s
  double switch_blend_per_s{10.0};  ///< rate at which a target switch blends in, (0, 100] 1/s
  DampingOptions damping{};         ///< singular_threshold, max_damping: (0, 1]
  double speed_fraction{0.8};       ///< of each joint's URDF velocity limit, (0, 1]
  double max_accel_rad_s2{30.0};    ///< per joint, smoothing, (0, 1000] rad/s^2
  /// A joint this close to a limit and moving toward it gets less weight in PBVS, [0, 1] rad
  double limit_zone_rad{0.15};
  /// Weights of the orientation error about the tool's x, y, z axes, [0, 1]
  /// each. The 4-DoF arm cannot reach every orientation: position always comes
  /// first, orientation is met within what position leaves free.
  Eigen::Vector3d orientation_weights{1.0, 1.0, 1.0};
  double stale_target_s{0.2};  ///< a target older than this is refused, (0, 10] s
  /// Blend of the joint-space guide: weight guide_min of motion toward q* when
  /// max_i |q*_i - q_i| is below guide_near_rad, pure motion toward q* above
  /// guide_far_rad, linear between; PBVS has the rest.
  double guide_near_rad{0.05};  ///< [0, 3] rad
  double guide_far_rad{0.3};    ///< (guide_near_rad, 6] rad
  double guide_min{0.5};        ///< [0, 1]
  /// An unreachable target is searched again only once it has moved this far.
  double retarget_m{0.005};   ///< [0, 1] m
  double retarget_rad{0.05};  ///< [0, pi] rad
  /// ... or once this long has passed (the other arm may have moved away).
  double unreachable_retry_s{0.5};  ///< [0, 60] s
  /// Joint configurations (rad) a goal may be reached through when the straight
  /// joint path to it is forbidden; each of size dof() within the limits.
  /// Empty: the zero configuration clamped into the limits (for the shipped
  /// arms: hanging straight down, the farthest from the safe volume).
  std::vector<Eigen::VectorXd> via_rad{};
  /// Further via configurations drawn uniformly within the limits (fixed seed,
  /// once), tried after via_rad: ways around the other arm where the fixed
  /// ones pass through it.
  int random_vias{16};  ///< [0, 1000]
  /// Spacing of the forbidden-predicate checks along the straight path to q*.
  double path_check_step_rad{0.02};  ///< (0, 1] rad
  /// Work of the joint-goal search per Step, counted in IK iterations plus
  /// forbidden-predicate checks (not in time: the same inputs give the same
  /// commands on any machine); a longer search goes on in the next Steps.
  int search_budget{60};  ///< [1, 1000000]
  /// The joint targets sent are q + dq dt plus what the last targets still
  /// led the measured joints by, up to this much per joint, [0, 0.5] rad.
  /// Servos that take positions in counts and follow them with a lag then
  /// move at the commanded speed, and steps below half a count add up
  /// instead of rounding away. 0: q + dq dt (an ideal arm).
  double command_lead_rad{0.0};
  ApproachIkOptions ik{};  ///< the joint-goal search

  /// `prefix` is the key path of this section in its file, ending in "." ("" at
  /// the top). @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

enum class ServoStatus {
  kMoving,         ///< a velocity toward the target was commanded
  kNoTarget,       ///< holding: no target set yet
  kStaleTarget,    ///< holding: the target is older than stale_target_s
  kInvalidTarget,  ///< holding: the target has NaN/Inf or is not a rigid transform
  kInvalidState,   ///< holding: q has NaN/Inf or the wrong size
  kSafeVolume,     ///< holding: every scaled step would enter the forbidden region
  kUnreachable,    ///< holding: no joint goal meets the target within limits and allowed
  kSearching,      ///< holding: the search for a first joint goal goes on next Step
};
const char* ServoStatusName(ServoStatus status);

struct ServoCommand {
  Eigen::VectorXd dq_rad_s;  ///< commanded joint velocities
  /// The joint targets to send: q + dq * dt, plus the last targets' lead over
  /// q up to ServoConfig::command_lead_rad.
  Eigen::VectorXd q_target_rad;
  double position_error_m = 0.0;  ///< |p_g - p_e|
  double rotation_error_rad = 0.0;
  ApproachError error;         ///< position, approach axis and roll errors at q
  Eigen::VectorXd q_goal_rad;  ///< the IK joint goal q* (empty while there is none)
  double guide_weight = 0.0;   ///< guide_min..1: the share of the motion toward q*
  double damping = 0.0;        ///< lambda of the primary task
  double min_singular = 0.0;   ///< smallest singular value of the position Jacobian
  double step_scale = 1.0;     ///< < 1 when speed or safe-volume limits shortened the step
};

/// True when the arm at joint positions q must not be commanded (e.g. it would
/// be inside the vehicle's safe volume): see servo/collision_predicate.h.
using ForbiddenPredicate = std::function<bool(const Eigen::VectorXd& q)>;

class ArmServo {
 public:
  /// `arm` must outlive the servo. `forbidden` usually includes the other arm
  /// (servo/collision_predicate.h); then pass the RightOfWay the other arm's
  /// servo shares, and this arm's seat in it (0 or 1; the other arm has the
  /// other seat), so that the arms never hold each other up for good.
  /// `right_of_way` (when not null) must outlive the servo.
  /// @throws ConfigError when config is invalid, a via configuration does not
  /// fit the arm or the seat is not 0 or 1.
  ArmServo(const ArmModel& arm, const ServoConfig& config, ForbiddenPredicate forbidden = {},
           RightOfWay* right_of_way = nullptr, int seat = 0);

  /// Forget motion history: the next command starts from rest, its joint
  /// targets from the measured joints.
  void Reset();
  /// A new target bMg (the grasp or pre-grasp in the arm base) observed at stamp_s.
  /// When the target changes to another grasp pass `is_switch`: the commanded
  /// velocity then stays continuous (the old command fades at switch_blend_per_s).
  void SetTarget(const Eigen::Isometry3d& bMg, double stamp_s, bool is_switch = false);

  /// Joint configurations the goal search also starts from (e.g. the planner's
  /// solutions for the grasp and its pre-catch pose); replaces earlier hints.
  void SetSeedHints(std::vector<Eigen::VectorXd> q_hints) { hints_ = std::move(q_hints); }
  /// One cycle at time now_s with measured joints q and period dt_s (> 0).
  /// Never throws; on any hold status dq is zero and q_target is q (or the last
  /// good q when q itself is invalid). With a RightOfWay, an arm held as
  /// kUnreachable while the other arm is held too may instead make way: it
  /// moves (kMoving) to a via configuration and searches again from there.
  ServoStatus Step(const Eigen::VectorXd& q, double now_s, double dt_s, ServoCommand* out);

  const ArmModel& arm() const { return arm_; }
  const ServoConfig& config() const { return config_; }

 private:
  ServoStatus Hold(const Eigen::VectorXd& q, ServoStatus status, ServoCommand* out);
  /// Step() before the post to the RightOfWay.
  ServoStatus Command(const Eigen::VectorXd& q, double now_s, double dt_s, ServoCommand* out);
  /// Makes way for the other arm when the RightOfWay says so: heads for the
  /// first via configuration away from q with an allowed path; false when it
  /// need not or cannot.
  bool MakeWay(const Eigen::VectorXd& q, double now_s, double to_target_m);
  enum class Goal { kReady, kSearching, kUnreachable };
  /// Updates q* (and the via point) for the current target within the Step's
  /// search budget: kReady with a goal (while a search for the moved target
  /// goes on, the last goal), kSearching while the first goal is searched,
  /// kUnreachable when the search found none.
  Goal UpdateJointGoal(const Eigen::VectorXd& q, double now_s);
  /// The search from joints q: its seeds are the closed-form solutions of
  /// the target (ApproachIk::ClosedFormSeeds), then, unless those are all
  /// there are (ApproachIk::closed_form_complete), q, the last goal, the hints
  /// and random ones.
  void StartSearch(const Eigen::VectorXd& q);
  /// Goes on with the search for at most *budget units (IK iterations and
  /// predicate checks; each spent is taken off *budget). True once it ended.
  bool ContinueSearch(int* budget);
  /// dq scaled to the speed limits (*scale: the factor), then moved at most
  /// max_accel * dt from the last command, then stopped at the joint limits.
  Eigen::VectorXd Limit(const Eigen::VectorXd& q, Eigen::VectorXd dq, double dt_s,
                        double* scale) const;
  /// True when no point of the straight joint path (q_from, q_to] is forbidden.
  bool PathAllowed(const Eigen::VectorXd& q_from, const Eigen::VectorXd& q_to) const;

  const ArmModel& arm_;
  ServoConfig config_;
  ForbiddenPredicate forbidden_;
  RightOfWay* right_of_way_;
  int seat_;
  PbvsTask pbvs_;
  ApproachIk ik_;
  bool has_target_ = false;
  Eigen::Isometry3d bMg_ = Eigen::Isometry3d::Identity();
  double target_stamp_s_ = 0.0;
  Eigen::VectorXd last_dq_;      // previous command (for smoothing and blending)
  Eigen::VectorXd switch_dq_;    // command at the last switch, fading out
  bool switch_pending_ = false;  // a switch was declared; the blend starts at the next Step
  double switch_time_s_ = -1.0;  // < 0: no blend active
  Eigen::VectorXd last_good_q_;
  Eigen::VectorXd last_q_target_;  // the last joint targets commanded (empty: none since a hold)
  // Joint goal q* and the target it solves; the last target no goal was found for.
  bool has_goal_ = false;
  Eigen::VectorXd q_goal_;
  Eigen::Isometry3d goal_bMg_ = Eigen::Isometry3d::Identity();
  bool has_via_ = false;
  bool making_way_ = false;  // heading for via_q_ without a goal, to let the other arm pass
  Eigen::VectorXd via_q_;
  std::vector<Eigen::VectorXd> via_;
  std::vector<Eigen::VectorXd> hints_;
  bool has_failed_ = false;
  Eigen::Isometry3d failed_bMg_ = Eigen::Isometry3d::Identity();
  double failed_at_s_ = 0.0;

  /// A straight joint path checked against the forbidden predicate one sample
  /// at a time, the goal end first (as PathAllowed).
  struct PathCheck {
    Eigen::VectorXd from, to;
    int samples = 0, next = 0;  // next: the sample to check, samples..1
  };
  /// The joint-goal search in progress (ApproachIk::Search with the via
  /// points, spread over Steps). Stages: iterating a seed, then for a
  /// converged q* its direct path, then each via point's two legs.
  struct Search {
    enum class Stage { kIk, kDirect, kToVia, kFromVia };
    bool active = false;
    bool found = false;  // once ended: a goal was found
    Eigen::VectorXd q_start;
    std::vector<Eigen::VectorXd> seeds;
    std::size_t next_seed = 0;  // of seeds, then random_seeds drawn from rng
    std::mt19937 rng;
    bool iterating = false;
    ApproachIkRun run;
    Stage stage = Stage::kIk;
    Eigen::VectorXd candidate;             // a converged q* being checked
    std::vector<Eigen::VectorXd> refused;  // q* refused already (not checked again)
    std::vector<signed char> to_via;       // PathAllowed(q_start, via_[v]), -1: not known
    std::size_t via = 0;
    PathCheck path;
  } search_;
  PathCheck MakePathCheck(const Eigen::VectorXd& from, const Eigen::VectorXd& to) const;
  /// One sample of `path` (one unit of budget); true once it ended, with *allowed.
  bool StepPath(PathCheck* path, bool* allowed) const;
};

}  // namespace aerograsp
