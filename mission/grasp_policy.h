// The grasp policy: every decision of a mission's grasp, as pure functions of
// explicit inputs (no devices, clock, threads or ground truth). The mission
// runner (app/runtime/mission_runner.h) reads the devices, asks the policy and carries
// out its answer; the planner state machine (mission/state_machines.h) keeps
// the attempt's state.
//
// The rules, in the order a grasp meets them:
//  - plan trigger: plan when the object is in view and within
//    near_tolerance_m of its grasp point under the body (ShouldPlan);
//  - first choice: the best ranked dual grasp (FirstChoice);
//  - switch: at each re-evaluation the followed pair is kept while it is
//    ranked and no pair scores switch_margin more, else the best is proposed
//    (DecideSwitch);
//  - debounce: a proposed switch is taken only after unreachable_to_switch
//    proposals in a row and never while a gripper closes (OnReevaluation);
//  - IK-branch gate: a followed pair solved again is taken only on the IK
//    branch it was followed on (OnFollowedBranch);
//  - close: both arms at their pre-catch poses, settle_s there, then in and
//    close, each only on a target on the object (TargetOnObject) and, with
//    close_together_m set, only once the other arm is that near its grasp too
//    (or closes, or waited close_wait_s: MayClose); grasped when both grippers
//    hold (NextPlannerStep);
//  - go in: an arm counts as at its pre-catch pose once it is there or past
//    it (moving in, closing, closed: AtOrPastPreCatch), so an arm that kept
//    its pair through a switch does not hold the other at its pre-catch pose;
//  - retry: an arm's sequence timed out, the object lost for lost_timeout_s
//    (a gripper that has begun closing finishes its close first:
//    ObjectLostTooLong), or both grippers closed without holding
//    (DecideAttempt);
//  - carried: from the moment one gripper holds, the object moves with it
//    (CarryingGripper) and that arm keeps still;
//  - re-aim: one gripper holds, the other's attempt ended (closed, timed out,
//    or no way to its target for carried_unreachable_s: the carried object
//    keeps still in the body, so that target stays out of reach): the free
//    arm aims at a pair it has not aimed at in this attempt, clear of edges,
//    nearest its joints, that clears the holding arm, at most max_reaims
//    times an attempt; with no such pair the holder
//    stays closed and the search is asked again for reaim_wait_s before the
//    attempt ends (DecideAttempt, RankReaim);
//  - give up: no plan within planning_timeout_s (PlanningGiveUp); after
//    max_attempts failed attempts the planner machine fails.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "grasp/planner.h"
#include "mission/state_machines.h"
#include "servo/grasp_sequence.h"

namespace aerograsp {

/// The policy's settings (the `policy` section of the mission config).
struct GraspPolicyConfig {
  /// Plan when the object is this near its grasp point under the body, (0, 1] m.
  double near_tolerance_m{0.03};
  /// both arms at their pre-catch poses this long before moving in, [0, 5] s
  double settle_s{0.2};
  int max_attempts{12};        ///< failed attempts (plans) before giving up, [1, 100]
  double lost_timeout_s{2.0};  ///< object lost this long while grasping: plan again, (0, 60] s
  /// A briefly lost object held in the world moves on with its filtered
  /// velocity, trusted less with time: at most this many seconds' worth
  /// (v tau (1 - exp(-t / tau))), [0, 60] s; 0 holds it still.
  double held_velocity_trust_s{0.0};
  /// ... not at all below this speed (a still object stays still), [0, 1] m/s
  double held_min_speed_mps{0.01};
  double held_max_carry_m{0.05};  ///< ... and at most this far, [0, 1] m
  /// without a feasible grasp (or the object in view), (0, 600] s
  double planning_timeout_s{10.0};
  /// A ranked followed pair is left only for one scoring this much more, [0, 10] (score units).
  double switch_margin{0.01};
  /// Re-evaluations in a row proposing a switch before it is taken, [1, 100].
  int unreachable_to_switch{5};
  /// Joint change between solutions beyond which a re-solved grasp is another IK branch, (0, 6.3]
  /// rad.
  double branch_jump_rad{0.15};
  /// ... plus this much per second since the last accepted solution, [0, 10] rad/s.
  double branch_drift_rad_per_s{0.5};
  int max_reaims{3};  ///< re-aims of the free arm per attempt while the other holds, [0, 100]
  /// With no pair for the free arm the holder stays closed this long, the
  /// search asked again at the re-evaluation rate (the carried object's
  /// estimate is refined frame by frame), before the attempt ends, [0, 60] s.
  double reaim_wait_s{2.0};
  /// One gripper carries the object and the free arm has found no way to its
  /// target this long: its attempt ends and it re-aims, [0, 60] s.
  double carried_unreachable_s{1.0};
  double home_tolerance_m{0.01};  ///< an arm this near its home tool position is back, (0, 0.2] m
  /// An arm closes only on a target this near its grasp on the object's
  /// current estimate, (0, 0.2] m (TargetOnObject).
  double target_on_object_m{0.01};
  /// An arm at its grasp pose closes only once the other arm's tool is this
  /// near its own grasp (or that arm closes, holds or has ended), so the
  /// grippers close one right after the other (the first to hold carries the
  /// object away from a free arm still on its way in), [0, 0.2] m; 0: each
  /// closes when it arrives (MayClose).
  double close_together_m{0.0};
  /// ... waiting at most this long at its grasp pose, [0, 60] s.
  double close_wait_s{1.0};

  /// @throws ConfigError "<source>: <prefix><field>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// The dual grasp the runner follows (contact-pair indices, -1: none yet).
struct SwitchState {
  int left_pair = -1;
  int right_pair = -1;
};

/// One re-evaluation's proposal.
struct SwitchDecision {
  enum class Status { kKeep, kSwitch, kNoGrasp };
  Status status = Status::kNoGrasp;
  DualGrasp grasp;  ///< the pair to follow now (valid unless kNoGrasp)
  bool current_feasible = false;
  std::string reason;  ///< one line for the log
  SwitchState next;    ///< the followed pair if this proposal is taken
};

/// What the policy keeps between decisions (owned by the runner, passed in).
struct GraspPolicyState {
  SwitchState followed;
  int switch_proposals_in_a_row = 0;  ///< re-evaluations in a row that proposed a switch
  int reaims = 0;                     ///< re-aims of the free arm in this attempt
  std::vector<int> aimed_pairs[2];    ///< pairs each arm aimed at in this attempt
};

/// Why each arm cannot take the followed pair (asked only when it left the ranking).
using WhyUnreachable = std::function<std::optional<std::pair<Infeasibility, Infeasibility>>()>;

/// Plan trigger: the planner is idle, the object in view and within
/// near_tolerance_m of its grasp point (off_m from it).
bool ShouldPlan(bool planner_idle, bool object_found, double off_m,
                const GraspPolicyConfig& config);

/// The dual grasp a new plan follows: the best ranked, null when none.
const DualGrasp* FirstChoice(const PlanResult& plan);

/// The switching rule: keep the followed pair while it is ranked and the best
/// scores at most switch_margin more (no flapping between near-equal pairs);
/// else propose the best, saying why (first choice, the followed pair became
/// unreachable, or a better one). kNoGrasp when nothing is ranked.
SwitchDecision DecideSwitch(const PlanResult& plan, const SwitchState& followed,
                            double switch_margin, const WhyUnreachable& why_unreachable = {});

/// What the runner does with a re-evaluation's proposal.
enum class ReevaluationAction {
  kNone,    ///< nothing (no grasp, or a switch not yet confirmed)
  kKeep,    ///< the followed pair stays (state.followed = decision.next)
  kSwitch,  ///< follow decision.grasp (state.followed = decision.next)
};

/// The debounce: a switch is taken once unreachable_to_switch re-evaluations in
/// a row proposed one, and not while either gripper closes (`closing`).
/// Updates state->switch_proposals_in_a_row and, on kKeep / kSwitch, state->followed.
ReevaluationAction OnReevaluation(const SwitchDecision& decision, bool closing,
                                  const GraspPolicyConfig& config, GraspPolicyState* state);

/// True while a gripper closes or has closed (no switch then).
bool Closing(GraspPhase left, GraspPhase right);

/// The IK-branch gate: a grasp solved again (q_new_rad) is followed only when
/// no joint moved branch_jump_rad + branch_drift_rad_per_s * since_s or more
/// from the last accepted solution (q_last_rad, since_s ago): a solution far in
/// joint space is another branch or depth and would throw the arm across.
bool OnFollowedBranch(const Eigen::VectorXd& q_new_rad, const Eigen::VectorXd& q_last_rad,
                      double since_s, const GraspPolicyConfig& config);

/// Give up planning: no plan for planning_timeout_s. The cause, or none.
std::optional<std::string> PlanningGiveUp(double planning_for_s, bool object_found,
                                          const GraspPolicyConfig& config);

/// An attempt in progress as the robot sees it.
struct AttemptView {
  GraspPhase phase[2] = {GraspPhase::kPreCatch, GraspPhase::kPreCatch};  ///< left, right
  bool holds[2] = {false, false};                                        ///< the grippers' readings
  double aperture_m[2] = {0.0, 0.0};                                     ///< the grippers' openings
  double lost_for_s = -1.0;          ///< the object out of view this long; < 0: in view
  bool one_gripper_carries = false;  ///< a re-aim is under way (one gripper holds)
  bool reaim_unavailable = false;    ///< the free arm's last search found no pair (not due again)
  double reaim_unavailable_for_s = -1.0;  ///< since the first search found none; < 0: none failed
  /// Each arm's servo has found no way to its target this long; < 0: it moves.
  double unreachable_for_s[2] = {-1.0, -1.0};
};

enum class AttemptAction {
  kContinue,  ///< go on (NextPlannerStep)
  kWait,      ///< the holding gripper is still closing
  kReaim,     ///< aim the free arm again (holder holds)
  kRetry,     ///< end the attempt and plan again (reason)
};

struct AttemptDecision {
  AttemptAction action = AttemptAction::kContinue;
  int holder = -1;     ///< kReaim: the holding arm (0 left, 1 right)
  std::string reason;  ///< kRetry: one line
};

/// The gripper that carries the object: the only one holding it (0 left,
/// 1 right), else -1. From its first hold the object moves with that gripper.
int CarryingGripper(const AttemptView& view);

/// Retry reasons and the re-aim rule (see the file comment).
AttemptDecision DecideAttempt(const AttemptView& view, const GraspPolicyState& state,
                              const GraspPolicyConfig& config);

/// An arm counts as at its pre-catch pose for the planner's "both at their
/// pre-catch poses" when it is there (at_precatch) or already past it: moving
/// in, closing or closed (a switch that changed only the other arm's pair
/// leaves this one going on). Without it, an arm that closed while the other
/// went back to a new pre-catch pose would keep the other waiting there.
bool AtOrPastPreCatch(GraspPhase phase, bool at_precatch);

/// The object lost too long ends the attempt: lost_for_s beyond
/// lost_timeout_s, and no gripper closing (a close that has begun takes
/// close_time_s and closes on the pose held where the object was last seen:
/// ended in the middle, its pads would open before they reach the object).
bool ObjectLostTooLong(double lost_for_s, bool a_gripper_closes, const GraspPolicyConfig& config);

/// The next planner signal of an attempt going on.
enum class PlannerStep { kNone, kAtPreCatch, kGoIn, kClosed };
PlannerStep NextPlannerStep(PlannerState state, bool both_at_precatch, double time_in_state_s,
                            bool both_done, bool both_hold, const GraspPolicyConfig& config);

/// The free arm's re-aim: among `candidates` that `clears` (of the holding
/// arm), those it has not aimed at (`aimed_pairs`) first, then those clear of
/// edges, then the nearest the arm's joints (cost_rad). The index, or -1 when
/// none clears.
int RankReaim(const std::vector<ArmGrasp>& candidates,
              const std::function<bool(const ArmGrasp&)>& clears,
              const std::vector<int>& aimed_pairs = {});

/// The close gate: the arm's target (target_d) lies within target_on_object_m
/// of its grasp on the object's current estimate (grasp_d), both in the body
/// frame. A target that could not follow the object (out of reach, or on
/// another IK branch, for a while) has fallen behind it and closing there
/// closes on nothing.
bool TargetOnObject(const Eigen::Vector3d& target_d, const Eigen::Vector3d& grasp_d,
                    const GraspPolicyConfig& config);

/// The close together: an arm at its grasp pose for waited_s may close when
/// close_together_m is 0, the other arm closes, holds or has timed out
/// (other_phase), is in its grasp phase within close_together_m of its grasp
/// on the object (other_error_m; infinite while its target stands off the
/// object), or the wait reached close_wait_s.
bool MayClose(GraspPhase other_phase, double other_error_m, double waited_s,
              const GraspPolicyConfig& config);

/// While the object is briefly lost (lost_for_s in [0, lost_timeout_s]) after
/// it was seen within the tracking radius, it is held at its last world pose.
bool HoldLastWorldPose(bool seen_before, bool found, double lost_for_s,
                       const GraspPolicyConfig& config);

/// How far an object held at its last world pose has moved unseen_s after the
/// frame it was last seen in, from its filtered world velocity v_w_mps: none
/// below held_min_speed_mps, v tau (1 - exp(-unseen_s / tau)) with tau
/// held_velocity_trust_s (the velocity trusted less as time passes), at most
/// held_max_carry_m.
Eigen::Vector3d HeldWorldDisplacement(const Eigen::Vector3d& v_w_mps, double unseen_s,
                                      const GraspPolicyConfig& config);

}  // namespace aerograsp
