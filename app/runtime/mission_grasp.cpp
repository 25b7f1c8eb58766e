#include "app/runtime/mission_grasp.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "app/runtime/mission_object.h"
#include "core/collision.h"

namespace aerograsp {
GraspScheduler::GraspScheduler(const MissionConfig& config, const Platform& platform,
                               const GraspPlanner& planner, const PlatformCollision& collision,
                               const Eigen::VectorXd* q, TrackedObject* object,
                               GraspMachines machines, ArmsDriver* driver,
                               MissionEvaluator* evaluator, MissionResult* result,
                               MissionRecord* record, std::function<Eigen::Isometry3d()> dMo_now,
                               std::function<void(const std::string&)> emergency,
                               std::function<void(const std::string&)> log)
    : config_(config),
      planner_(planner),
      collision_(collision),
      q_(q),
      object_(object),
      sm_(machines),
      driver_(driver),
      result_(result),
      record_(record),
      dMo_now_(std::move(dMo_now)),
      emergency_(std::move(emergency)),
      log_(std::move(log)),
      arms_(platform, planner, collision, config, q, evaluator, log_) {}

GraspScheduler::~GraspScheduler() { Wait(); }

void GraspScheduler::Wait() {
  if (planning_.valid()) planning_.wait();
  if (reevaluating_.valid()) reevaluating_.wait();
}

void GraspScheduler::AwaitDue(double t) {
  // Taken (or dropped: not asked for in the last cycle) by Plan.
  if (planning_.valid() && (!plan_wanted_ || t + 1e-9 >= planning_due_s_)) planning_.wait();
  // Taken (or dropped: the attempt ended) by Reevaluate.
  if (reevaluating_.valid() && (!Reevaluating() || t + 1e-9 >= next_reevaluate_s_))
    reevaluating_.wait();
}

bool GraspScheduler::Reevaluating() const {
  // One arm holding: its pair is not switched.
  return sm_.global->state() == GlobalState::kGrasping && active() && object_->holder() < 0;
}

bool GraspScheduler::active() const {
  const PlannerState s = sm_.planner->state();
  return s == PlannerState::kServoing || s == PlannerState::kApproachPose ||
         s == PlannerState::kGrasping;
}

PlanQuery GraspScheduler::Query() const {
  PlanQuery query;
  query.dMo = dMo_now_();
  query.q_left = q_[0];
  query.q_right = q_[1];
  return query;
}

std::optional<GraspScheduler::AskedPlan> GraspScheduler::DuePlan(double t, int purpose) {
  plan_wanted_ = true;
  if (planning_.valid() && planning_for_ != purpose) DropPlan();
  if (!planning_.valid()) {
    planning_query_ = Query();
    planning_for_ = purpose;
    planning_due_s_ = t + 1.0 / config_.reevaluate_rate_hz;
    const GraspPlanner* planner = &planner_;
    const PlanQuery query = planning_query_;
    planning_ = std::async(std::launch::async, [planner, query] { return planner->Plan(query); });
    return std::nullopt;
  }
  if (t + 1e-9 < planning_due_s_) return std::nullopt;
  return AskedPlan{planning_query_, planning_.get()};
}

void GraspScheduler::DropPlan() {
  if (planning_.valid()) planning_.get();
}

bool GraspScheduler::AimFreeArm(double t, int holding, const AskedPlan& asked) {
  const int free = 1 - holding;
  const PlanResult& plan = asked.result;
  const std::vector<ArmGrasp>& candidates = free == 0 ? plan.left : plan.right;
  const Eigen::VectorXd& q_held = q_[holding];
  const double margin = planner_.config().arms_margin_m;
  const auto collide = [&](const Eigen::VectorXd& q_free) {
    return free == 0 ? collision_.ArmsCollide(q_free, q_held, margin)
                     : collision_.ArmsCollide(q_held, q_free, margin);
  };
  std::vector<int>& aimed = policy_.aimed_pairs[free];
  const int followed_free = free == 0 ? policy_.followed.left_pair : policy_.followed.right_pair;
  if (followed_free >= 0 && std::find(aimed.begin(), aimed.end(), followed_free) == aimed.end())
    aimed.push_back(followed_free);
  const int best = RankReaim(
      candidates, [&](const ArmGrasp& g) { return !collide(g.q_grasp) && !collide(g.q_precatch); },
      aimed);
  if (best < 0) {
    if (reaim_failed_since_s_ >= 0) return false;  // logged at its first search
    log_(
        fmt::format("planner: the {} gripper holds the object but no pair clears it for the {} "
                    "arm ({} feasible for it{})",
                    kArmNames[holding], kArmNames[free], candidates.size(),
                    candidates.empty() ? "" : ", each too near the holding arm"));
    return false;
  }
  const ArmGrasp& g = candidates[best];
  object_->CarriedBy(holding, dMo_now_());
  (free == 0 ? policy_.followed.left_pair : policy_.followed.right_pair) = g.pair;
  // The holding arm's pair is not solved again.
  (holding == 0 ? policy_.followed.left_pair : policy_.followed.right_pair) = -1;
  arms_.Aim(free, g, t);
  ++result_->attempts;
  log_(
      fmt::format("planner: the {} gripper holds the object and stays closed; the {} arm "
                  "re-aims at pair {} ({} feasible for it)",
                  kArmNames[holding], kArmNames[free], g.pair, candidates.size()));
  return true;
}

bool GraspScheduler::StartPlan(double t, const AskedPlan& asked) {
  const PlanQuery& query = asked.query;
  const PlanResult& plan = asked.result;
  const DualGrasp* best = FirstChoice(plan);
  if (!best) {
    if (!logged_no_grasp_) {
      std::string why;
      for (int a = 0; a < 2; ++a) {
        const std::string r = DescribeReasons(a == 0 ? plan.left_stats : plan.right_stats);
        if (!r.empty()) why += fmt::format("; {}: {}", kArmNames[a], r);
      }
      log_(
          fmt::format("planner: no feasible dual grasp yet ({} left, {} right feasible{}; the "
                      "object {:.0f} mm from its grasp point under the body); waiting",
                      plan.left.size(), plan.right.size(), why,
                      1e3 * (query.dMo.translation() - config_.grasp_dto_m).norm()));
      logged_no_grasp_ = true;
    }
    return false;
  }
  logged_no_grasp_ = false;
  retracting_ = false;
  policy_.followed = {best->left.pair, best->right.pair};
  object_->LockLength();
  arms_.Start(*best, query.dMo, t);
  ++result_->attempts;
  sm_.arms->Move(t, "servoing to the pre-catch poses");
  sm_.planner->Planned(
      t, fmt::format("pairs L{} R{} of {} ranked: epsilon {:.3f}, score {:.3f}", best->left.pair,
                     best->right.pair, plan.ranked.size(), best->epsilon, best->score));
  next_reevaluate_s_ = t + 1.0 / config_.reevaluate_rate_hz;
  return true;
}

void GraspScheduler::StopArms(double t, const std::string& cause) {
  sm_.arms->Hold(t, cause);
  arms_.Hold(driver_);
  for (int a = 0; a < 2; ++a) driver_->SetGripper(kSides[a], GripperCommand::kOpen);
  a_gripper_holds_ = false;  // opened, neither holds
  gripper_holds_[0] = gripper_holds_[1] = false;
}

void GraspScheduler::Plan(double t) {
  // A plan in flight that the last cycle did not ask for answers a question
  // that is no longer asked.
  if (!plan_wanted_) DropPlan();
  plan_wanted_ = false;
  if (sm_.global->state() != GlobalState::kGrasping) return;
  const PlannerState state = sm_.planner->state();
  const bool found = sm_.vision->state() == VisionState::kFound;
  if (state == PlannerState::kPlanning) {
    if (planning_since_s_ < 0) planning_since_s_ = t;
    std::optional<AskedPlan> plan;
    if (found) plan = DuePlan(t, kForDualGrasp);
    if (plan && StartPlan(t, *plan)) {
      planning_since_s_ = -1.0;
    } else if (const auto cause = PlanningGiveUp(t - planning_since_s_, found, config_.policy)) {
      sm_.global->GiveUp(t, *cause);
    }
    return;
  }
  if (state == PlannerState::kFailed) {
    sm_.global->GiveUp(t, "every grasp attempt failed");
    return;
  }
  if (!active()) return;

  AttemptView view;
  for (int a = 0; a < 2; ++a) {
    view.phase[a] = arms_.phase(a);
    // Each gripper read once per cycle (on hardware a read is a bus transaction).
    const GripperState g = driver_->Gripper(kSides[a]);
    view.holds[a] = g.holding;
    view.aperture_m[a] = g.aperture_m;
    view.unreachable_for_s[a] = arms_.unreachable_for_s(a, t);
    gripper_holds_[a] = g.holding;
  }
  const int carrier = CarryingGripper(view);
  if (carrier >= 0 && object_->holder() < 0) {
    object_->CarriedBy(carrier, dMo_now_());
    log_(fmt::format("planner: the {} gripper holds the object: it moves with that gripper now",
                     kArmNames[carrier]));
  }
  // The free gripper's close on nothing says where the carried object's end
  // lies (once per close).
  const int holder = object_->holder();
  const bool free_closed_empty =
      holder >= 0 && view.phase[1 - holder] == GraspPhase::kDone && !view.holds[1 - holder];
  if (free_closed_empty && !free_closed_empty_) object_->ClosedOnNothing(1 - holder);
  free_closed_empty_ = free_closed_empty;
  view.lost_for_s = object_->lost_for_s(t);
  view.one_gripper_carries = holder >= 0;
  a_gripper_holds_ = view.holds[0] || view.holds[1];
  // A re-aim search that found no pair is asked again at the re-evaluation rate.
  view.reaim_unavailable = t + 1e-9 < next_reaim_s_;
  view.reaim_unavailable_for_s = reaim_failed_since_s_ < 0 ? -1.0 : t - reaim_failed_since_s_;
  AttemptDecision decision = DecideAttempt(view, policy_, config_.policy);
  if (decision.action == AttemptAction::kReaim) {
    const std::optional<AskedPlan> plan = DuePlan(t, decision.holder);
    if (!plan) return;  // asked: the holder holds, the free arm waits
    if (AimFreeArm(t, decision.holder, *plan)) {
      ++policy_.reaims;
      reaim_failed_since_s_ = -1.0;
      return;
    }
    if (reaim_failed_since_s_ < 0) reaim_failed_since_s_ = t;
    next_reaim_s_ = t + 1.0 / config_.reevaluate_rate_hz;
    view.reaim_unavailable = true;
    view.reaim_unavailable_for_s = t - reaim_failed_since_s_;
    decision = DecideAttempt(view, policy_, config_.policy);
  }
  if (decision.action == AttemptAction::kWait) return;
  if (decision.action == AttemptAction::kRetry) {
    object_->Released();
    policy_.reaims = 0;
    for (std::vector<int>& aimed : policy_.aimed_pairs) aimed.clear();
    reaim_failed_since_s_ = -1.0;
    next_reaim_s_ = 0.0;
    sm_.planner->Retry(t, decision.reason);
    StopArms(t, "attempt ended: " + decision.reason);
    // Held at their grasp poses the arms hide part of the object from the
    // camera; home, they are out of its view for the next search and plan.
    sm_.arms->Move(t, "back home, out of the camera's view, to plan again");
    retracting_ = true;
    arms_.SeedHome();
    planning_since_s_ = t;
    return;
  }
  const bool done = view.phase[0] == GraspPhase::kDone && view.phase[1] == GraspPhase::kDone;
  switch (NextPlannerStep(state, arms_.both_at_precatch(), sm_.planner->TimeIn(t), done,
                          view.holds[0] && view.holds[1], config_.policy)) {
    case PlannerStep::kAtPreCatch:
      sm_.planner->AtPreCatch(t);
      break;
    case PlannerStep::kGoIn:
      sm_.planner->GoIn(t);
      arms_.GoIn();
      break;
    case PlannerStep::kClosed:
      sm_.planner->Closed(t);
      holding_ = true;
      result_->time_to_grasp_s = t;
      sm_.arms->Hold(t, "grasped: holding the object");
      sm_.global->Grasped(t);
      break;
    case PlannerStep::kNone:
      break;
  }
}

void GraspScheduler::Reevaluate(double t) {
  if (!Reevaluating()) {
    if (reevaluating_.valid()) reevaluating_.get();  // an answer for a plan that has ended
    return;
  }
  if (t + 1e-9 < next_reevaluate_s_) return;
  next_reevaluate_s_ = t + 1.0 / config_.reevaluate_rate_hz;
  if (reevaluating_.valid()) {
    const SwitchDecision decision = reevaluating_.get();
    const SwitchState before = policy_.followed;
    const bool closing = Closing(arms_.phase(0), arms_.phase(1));
    if (OnReevaluation(decision, closing, config_.policy, &policy_) ==
        ReevaluationAction::kSwitch) {
      arms_.Switch(decision.grasp, reevaluate_dMo_, before, t);
      ++result_->grasp_switches;
      const int left = decision.grasp.left.pair, right = decision.grasp.right.pair;
      if (record_) record_->switches.push_back({t, left, right, decision.reason});
      sm_.planner->Switched(
          t, fmt::format("switch to pairs L{} R{}: {}", left, right, decision.reason));
    }
  }
  reevaluate_dMo_ = dMo_now_();
  PlanQuery query = Query();
  query.dMo = reevaluate_dMo_;
  const GraspPlanner* planner = &planner_;
  const SwitchState followed = policy_.followed;
  const double margin = config_.policy.switch_margin;
  reevaluating_ = std::async(std::launch::async, [planner, query, followed, margin] {
    // Why each arm cannot take the followed pair, asked only when it left the ranking.
    const auto why_unreachable = [&]() -> std::optional<std::pair<Infeasibility, Infeasibility>> {
      const int pairs = static_cast<int>(planner->contacts().pairs.size());
      if (followed.left_pair >= pairs || followed.right_pair >= pairs) return std::nullopt;
      Infeasibility wl = Infeasibility::kNone, wr = Infeasibility::kNone;
      ArmGrasp unused;
      planner->EvaluateArm(Side::kLeft, followed.left_pair, query.dMo, query.q_left, &unused, &wl);
      planner->EvaluateArm(Side::kRight, followed.right_pair, query.dMo, query.q_right, &unused,
                           &wr);
      return std::make_pair(wl, wr);
    };
    return DecideSwitch(planner->PlanFront(query, followed.left_pair, followed.right_pair),
                        followed, margin, why_unreachable);
  });
}

void GraspScheduler::Servo(double t, double dt_s) {
  if (!sm_.arms->commands_allowed() || sm_.global->state() != GlobalState::kGrasping) return;
  std::optional<std::string> emergency;
  if (retracting_ && sm_.planner->state() == PlannerState::kPlanning) {
    if (arms_.Retract(t, dt_s, driver_, &emergency)) {
      retracting_ = false;
      sm_.arms->Hold(t, "home, out of the camera's view");
    }
  } else if (active()) {
    FollowView view;
    view.dMo = dMo_now_();
    view.object_held_in_world = object_->HeldInWorld(t);
    for (int a = 0; a < 2; ++a) view.holds[a] = gripper_holds_[a];
    view.stamp_s =
        view.object_held_in_world || object_->holder() >= 0 ? t : object_->last_found_stamp_s();
    emergency = arms_.Step(t, dt_s, view, policy_.followed, driver_);
  }
  if (emergency) emergency_(*emergency);
}

}  // namespace aerograsp
