#include "mission/grasp_policy.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "core/config.h"

namespace aerograsp {
namespace {

bool SamePairs(const DualGrasp& d, const SwitchState& s) {
  return d.left.pair == s.left_pair && d.right.pair == s.right_pair;
}

}  // namespace

void GraspPolicyConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "near_tolerance_m", near_tolerance_m, 1e-6, 1.0, "m");
  CheckRange(source, prefix + "settle_s", settle_s, 0.0, 5.0, "s");
  CheckRange(source, prefix + "max_attempts", max_attempts, 1, 100, "");
  CheckRange(source, prefix + "lost_timeout_s", lost_timeout_s, 1e-6, 60.0, "s");
  CheckRange(source, prefix + "held_velocity_trust_s", held_velocity_trust_s, 0.0, 60.0, "s");
  CheckRange(source, prefix + "held_min_speed_mps", held_min_speed_mps, 0.0, 1.0, "m/s");
  CheckRange(source, prefix + "held_max_carry_m", held_max_carry_m, 0.0, 1.0, "m");
  CheckRange(source, prefix + "planning_timeout_s", planning_timeout_s, 1e-6, 600.0, "s");
  CheckRange(source, prefix + "switch_margin", switch_margin, 0.0, 10.0, "");
  CheckRange(source, prefix + "unreachable_to_switch", unreachable_to_switch, 1, 100, "");
  CheckRange(source, prefix + "branch_jump_rad", branch_jump_rad, 1e-6, 6.3, "rad");
  CheckRange(source, prefix + "branch_drift_rad_per_s", branch_drift_rad_per_s, 0.0, 10.0, "rad/s");
  CheckRange(source, prefix + "max_reaims", max_reaims, 0, 100, "");
  CheckRange(source, prefix + "reaim_wait_s", reaim_wait_s, 0.0, 60.0, "s");
  CheckRange(source, prefix + "carried_unreachable_s", carried_unreachable_s, 0.0, 60.0, "s");
  CheckRange(source, prefix + "home_tolerance_m", home_tolerance_m, 1e-6, 0.2, "m");
  CheckRange(source, prefix + "target_on_object_m", target_on_object_m, 1e-6, 0.2, "m");
  CheckRange(source, prefix + "close_together_m", close_together_m, 0.0, 0.2, "m");
  CheckRange(source, prefix + "close_wait_s", close_wait_s, 0.0, 60.0, "s");
}

bool ShouldPlan(bool planner_idle, bool object_found, double off_m,
                const GraspPolicyConfig& config) {
  return planner_idle && object_found && off_m < config.near_tolerance_m;
}

const DualGrasp* FirstChoice(const PlanResult& plan) {
  return plan.ranked.empty() ? nullptr : &plan.ranked.front();
}

SwitchDecision DecideSwitch(const PlanResult& plan, const SwitchState& followed,
                            double switch_margin, const WhyUnreachable& why_unreachable) {
  SwitchDecision decision;
  const DualGrasp* current = nullptr;
  for (const DualGrasp& d : plan.ranked) {
    if (SamePairs(d, followed)) {
      current = &d;
      break;
    }
  }
  decision.current_feasible = current != nullptr;
  std::ostringstream why;
  if (plan.ranked.empty()) {
    decision.status = SwitchDecision::Status::kNoGrasp;
    why << "no feasible dual grasp (left " << plan.left_stats.feasible << ", right "
        << plan.right_stats.feasible << " feasible single grasps)";
    decision.reason = why.str();
    decision.next = SwitchState{};
    return decision;
  }
  const DualGrasp& best = plan.ranked.front();
  if (current && best.score <= current->score + switch_margin) {
    decision.status = SwitchDecision::Status::kKeep;
    decision.grasp = *current;
    why << "keep pair (" << current->left.pair << ", " << current->right.pair << "), score "
        << current->score;
  } else {
    decision.status = SwitchDecision::Status::kSwitch;
    decision.grasp = best;
    if (followed.left_pair < 0) {
      why << "first choice";
    } else if (!current) {
      why << "pair (" << followed.left_pair << ", " << followed.right_pair
          << ") became unreachable";
      const auto reasons = why_unreachable ? why_unreachable() : std::nullopt;
      if (reasons) {
        why << " (left: " << InfeasibilityName(reasons->first)
            << ", right: " << InfeasibilityName(reasons->second);
        if (reasons->first == Infeasibility::kNone && reasons->second == Infeasibility::kNone)
          why << ", pair: arms or quality";
        why << ")";
      }
    } else {
      why << "pair (" << best.left.pair << ", " << best.right.pair << ") scores " << best.score
          << " > current " << current->score << " + margin " << switch_margin;
    }
    why << " -> pair (" << best.left.pair << ", " << best.right.pair << ")";
  }
  decision.reason = why.str();
  decision.next = SwitchState{decision.grasp.left.pair, decision.grasp.right.pair};
  return decision;
}

ReevaluationAction OnReevaluation(const SwitchDecision& decision, bool closing,
                                  const GraspPolicyConfig& config, GraspPolicyState* state) {
  // A pair unreachable at one re-evaluation may be reachable at the next (the
  // sway brings the object back): switch only when it stays unreachable.
  const bool proposes = decision.status == SwitchDecision::Status::kSwitch;
  state->switch_proposals_in_a_row = proposes ? state->switch_proposals_in_a_row + 1 : 0;
  if (proposes && !closing && state->switch_proposals_in_a_row >= config.unreachable_to_switch) {
    state->switch_proposals_in_a_row = 0;
    state->followed = decision.next;
    return ReevaluationAction::kSwitch;
  }
  if (decision.status == SwitchDecision::Status::kKeep) {
    state->followed = decision.next;
    return ReevaluationAction::kKeep;
  }
  return ReevaluationAction::kNone;
}

bool Closing(GraspPhase left, GraspPhase right) {
  const auto closing = [](GraspPhase p) {
    return p == GraspPhase::kClose || p == GraspPhase::kDone;
  };
  return closing(left) || closing(right);
}

bool OnFollowedBranch(const Eigen::VectorXd& q_new_rad, const Eigen::VectorXd& q_last_rad,
                      double since_s, const GraspPolicyConfig& config) {
  return (q_new_rad - q_last_rad).cwiseAbs().maxCoeff() <
         config.branch_jump_rad + config.branch_drift_rad_per_s * since_s;
}

std::optional<std::string> PlanningGiveUp(double planning_for_s, bool object_found,
                                          const GraspPolicyConfig& config) {
  if (planning_for_s <= config.planning_timeout_s) return std::nullopt;
  return object_found
             ? fmt::format("no feasible dual grasp within {:.0f} s", config.planning_timeout_s)
             : fmt::format("the object was not in view for {:.0f} s to plan again",
                           config.planning_timeout_s);
}

bool TargetOnObject(const Eigen::Vector3d& target_d, const Eigen::Vector3d& grasp_d,
                    const GraspPolicyConfig& config) {
  return (target_d - grasp_d).norm() <= config.target_on_object_m;
}

bool MayClose(GraspPhase other_phase, double other_error_m, double waited_s,
              const GraspPolicyConfig& config) {
  if (config.close_together_m <= 0.0 || other_phase == GraspPhase::kClose ||
      other_phase == GraspPhase::kDone || other_phase == GraspPhase::kTimedOut) {
    return true;
  }
  return (other_phase == GraspPhase::kGrasp && other_error_m <= config.close_together_m) ||
         waited_s >= config.close_wait_s;
}

int CarryingGripper(const AttemptView& view) {
  if (view.holds[0] == view.holds[1]) return -1;
  return view.holds[0] ? 0 : 1;
}

AttemptDecision DecideAttempt(const AttemptView& view, const GraspPolicyState& state,
                              const GraspPolicyConfig& config) {
  AttemptDecision d;
  std::string retry;
  for (int a = 0; a < 2; ++a) {
    if (view.phase[a] == GraspPhase::kTimedOut)
      retry = fmt::format("{} arm timed out", kArmNames[a]);
  }
  const bool a_gripper_closes =
      view.phase[0] == GraspPhase::kClose || view.phase[1] == GraspPhase::kClose;
  if (ObjectLostTooLong(view.lost_for_s, a_gripper_closes, config) && !view.one_gripper_carries) {
    retry = fmt::format("object lost for {:.1f} s", view.lost_for_s);
  }
  const bool done = view.phase[0] == GraspPhase::kDone && view.phase[1] == GraspPhase::kDone;
  // One gripper holds: it stays closed (opened, it would drop the object).
  // Once it has closed and the other's attempt has ended (closed on nothing,
  // timed out, or the object hidden by the fingers), the free arm aims again.
  if (const int holder = CarryingGripper(view); holder >= 0) {
    const GraspPhase free_phase = view.phase[1 - holder];
    const double free_unreachable_for_s = view.unreachable_for_s[1 - holder];
    const bool free_ended = free_phase == GraspPhase::kDone ||
                            free_phase == GraspPhase::kTimedOut || !retry.empty() ||
                            free_unreachable_for_s >= config.carried_unreachable_s;
    if (view.phase[holder] != GraspPhase::kDone) {
      if (free_ended) {
        d.action = AttemptAction::kWait;  // still closing
        return d;
      }
    } else if (free_ended && state.reaims < config.max_reaims) {
      if (!view.reaim_unavailable) {
        d.action = AttemptAction::kReaim;
        d.holder = holder;
        return d;
      }
      // No pair for the free arm yet: opened, the holder would drop a good
      // half-grasp; it stays closed while the search is asked again.
      if (view.reaim_unavailable_for_s <= config.reaim_wait_s) {
        d.action = AttemptAction::kWait;
        return d;
      }
      d.action = AttemptAction::kRetry;
      d.reason =
          fmt::format("the {} gripper holds but the {} arm found no pair for {:.1f} s",
                      kArmNames[holder], kArmNames[1 - holder], view.reaim_unavailable_for_s);
      return d;
    }
  }
  if (done && !(view.holds[0] && view.holds[1])) {
    retry = fmt::format(
        "the grippers closed without holding the object (left {} at {:.0f} mm, right {} at {:.0f} "
        "mm)",
        view.holds[0] ? "holds" : "empty", 1e3 * view.aperture_m[0],
        view.holds[1] ? "holds" : "empty", 1e3 * view.aperture_m[1]);
  }
  if (!retry.empty()) {
    d.action = AttemptAction::kRetry;
    d.reason = retry;
  }
  return d;
}

bool AtOrPastPreCatch(GraspPhase phase, bool at_precatch) {
  return at_precatch || phase == GraspPhase::kGrasp || phase == GraspPhase::kClose ||
         phase == GraspPhase::kDone;
}

bool ObjectLostTooLong(double lost_for_s, bool a_gripper_closes, const GraspPolicyConfig& config) {
  return lost_for_s >= 0 && lost_for_s > config.lost_timeout_s && !a_gripper_closes;
}

PlannerStep NextPlannerStep(PlannerState state, bool both_at_precatch, double time_in_state_s,
                            bool both_done, bool both_hold, const GraspPolicyConfig& config) {
  switch (state) {
    case PlannerState::kServoing:
      return both_at_precatch ? PlannerStep::kAtPreCatch : PlannerStep::kNone;
    case PlannerState::kApproachPose:
      return time_in_state_s >= config.settle_s ? PlannerStep::kGoIn : PlannerStep::kNone;
    case PlannerState::kGrasping:
      return both_done && both_hold ? PlannerStep::kClosed : PlannerStep::kNone;
    default:
      return PlannerStep::kNone;
  }
}

int RankReaim(const std::vector<ArmGrasp>& candidates,
              const std::function<bool(const ArmGrasp&)>& clears,
              const std::vector<int>& aimed_pairs) {
  // A pair not aimed at yet first (the last aim there closed on nothing or
  // found no way in), then grasps clear of the faces' edges (one near an end
  // closes past it with a few millimetres of error), then the nearest the
  // arm's joints.
  const auto key = [&](const ArmGrasp& g) {
    const bool aimed =
        std::find(aimed_pairs.begin(), aimed_pairs.end(), g.pair) != aimed_pairs.end();
    return std::make_tuple(aimed, !g.clear_of_edges, g.cost_rad);
  };
  int best = -1;
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    if (!clears(candidates[i])) continue;
    if (best < 0 || key(candidates[i]) < key(candidates[best])) best = i;
  }
  return best;
}

bool HoldLastWorldPose(bool seen_before, bool found, double lost_for_s,
                       const GraspPolicyConfig& config) {
  return seen_before && !found && lost_for_s >= 0 && lost_for_s <= config.lost_timeout_s;
}

Eigen::Vector3d HeldWorldDisplacement(const Eigen::Vector3d& v_w_mps, double unseen_s,
                                      const GraspPolicyConfig& config) {
  const double speed = v_w_mps.norm();
  const double tau = config.held_velocity_trust_s;
  if (unseen_s <= 0.0 || tau <= 0.0 || speed < config.held_min_speed_mps) {
    return Eigen::Vector3d::Zero();
  }
  const double travel_m =
      std::min(speed * tau * (1.0 - std::exp(-unseen_s / tau)), config.held_max_carry_m);
  return v_w_mps * (travel_m / speed);
}

}  // namespace aerograsp
