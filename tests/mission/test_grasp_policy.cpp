#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/config.h"
#include "mission/grasp_policy.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

DualGrasp Dual(int left, int right, double score) {
  DualGrasp d;
  d.left.pair = left;
  d.left.side = Side::kLeft;
  d.right.pair = right;
  d.right.side = Side::kRight;
  d.score = score;
  return d;
}

PlanResult Ranked(std::vector<DualGrasp> ranked) {
  PlanResult plan;
  plan.ranked = std::move(ranked);
  return plan;
}

SwitchDecision Proposal(SwitchDecision::Status status, int left = 1, int right = 2) {
  SwitchDecision d;
  d.status = status;
  d.grasp = Dual(left, right, 1.0);
  d.next = {left, right};
  return d;
}

// ---- Plan trigger -------------------------------------------------------------------

TEST(GraspPolicyTest, PlansOnlyWithTheObjectInViewNearItsGraspPoint) {
  const GraspPolicyConfig config;  // near_tolerance_m 0.03
  EXPECT_TRUE(ShouldPlan(true, true, 0.02, config));
  EXPECT_FALSE(ShouldPlan(true, true, 0.04, config));   // too far from the grasp point
  EXPECT_FALSE(ShouldPlan(true, false, 0.02, config));  // not in view
  EXPECT_FALSE(ShouldPlan(false, true, 0.02, config));  // a plan is under way
}

TEST(GraspPolicyTest, ANewPlanFollowsTheBestRankedGrasp) {
  const PlanResult plan = Ranked({Dual(3, 4, 0.9), Dual(1, 2, 0.5)});
  ASSERT_NE(FirstChoice(plan), nullptr);
  EXPECT_EQ(FirstChoice(plan)->left.pair, 3);
  EXPECT_EQ(FirstChoice(Ranked({})), nullptr);
}

// ---- Switch -------------------------------------------------------------------------

TEST(GraspPolicyTest, KeepsTheFollowedPairWhileNoneScoresTheMarginMore) {
  const PlanResult plan = Ranked({Dual(1, 2, 1.005), Dual(3, 4, 1.0)});
  const SwitchDecision d = DecideSwitch(plan, {3, 4}, 0.01);
  EXPECT_EQ(d.status, SwitchDecision::Status::kKeep);
  EXPECT_TRUE(d.current_feasible);
  EXPECT_EQ(d.grasp.left.pair, 3);
  EXPECT_EQ(d.next.left_pair, 3);
  EXPECT_EQ(d.next.right_pair, 4);
}

TEST(GraspPolicyTest, ProposesAPairScoringMoreThanTheMargin) {
  const PlanResult plan = Ranked({Dual(1, 2, 1.02), Dual(3, 4, 1.0)});
  const SwitchDecision d = DecideSwitch(plan, {3, 4}, 0.01);
  EXPECT_EQ(d.status, SwitchDecision::Status::kSwitch);
  EXPECT_TRUE(d.current_feasible);
  EXPECT_EQ(d.next.left_pair, 1);
  EXPECT_EQ(d.next.right_pair, 2);
  EXPECT_THAT(d.reason, HasSubstr("scores"));
}

TEST(GraspPolicyTest, ProposesTheBestWhenTheFollowedPairLeftTheRankingAndSaysWhy) {
  const PlanResult plan = Ranked({Dual(1, 2, 0.5)});
  const SwitchDecision d = DecideSwitch(plan, {7, 8}, 0.01, [] {
    return std::make_optional(std::make_pair(Infeasibility::kUnreachable, Infeasibility::kNone));
  });
  EXPECT_EQ(d.status, SwitchDecision::Status::kSwitch);
  EXPECT_FALSE(d.current_feasible);
  EXPECT_EQ(d.next.left_pair, 1);
  EXPECT_EQ(d.reason,
            "pair (7, 8) became unreachable (left: unreachable, right: feasible) -> pair (1, 2)");
}

TEST(GraspPolicyTest, TheFirstProposalIsTheBestAndNothingRankedIsNoGrasp) {
  const SwitchDecision first = DecideSwitch(Ranked({Dual(1, 2, 0.5)}), SwitchState{}, 0.01);
  EXPECT_EQ(first.status, SwitchDecision::Status::kSwitch);
  EXPECT_THAT(first.reason, HasSubstr("first choice"));
  const SwitchDecision none = DecideSwitch(Ranked({}), {1, 2}, 0.01);
  EXPECT_EQ(none.status, SwitchDecision::Status::kNoGrasp);
  EXPECT_EQ(none.next.left_pair, -1);
  EXPECT_THAT(none.reason, HasSubstr("no feasible dual grasp"));
}

// ---- Debounce -----------------------------------------------------------------------

TEST(GraspPolicyTest, ASwitchIsTakenOnlyAfterEnoughProposalsInARow) {
  GraspPolicyConfig config;
  config.unreachable_to_switch = 5;
  GraspPolicyState state;
  state.followed = {3, 4};
  const SwitchDecision proposal = Proposal(SwitchDecision::Status::kSwitch, 1, 2);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(OnReevaluation(proposal, false, config, &state), ReevaluationAction::kNone) << i;
    EXPECT_EQ(state.followed.left_pair, 3);
  }
  EXPECT_EQ(OnReevaluation(proposal, false, config, &state), ReevaluationAction::kSwitch);
  EXPECT_EQ(state.followed.left_pair, 1);
  EXPECT_EQ(state.followed.right_pair, 2);
  EXPECT_EQ(state.switch_proposals_in_a_row, 0);
}

TEST(GraspPolicyTest, AKeepBetweenProposalsRestartsTheCount) {
  GraspPolicyConfig config;
  config.unreachable_to_switch = 3;
  GraspPolicyState state;
  const SwitchDecision proposal = Proposal(SwitchDecision::Status::kSwitch, 1, 2);
  OnReevaluation(proposal, false, config, &state);
  OnReevaluation(proposal, false, config, &state);
  EXPECT_EQ(OnReevaluation(Proposal(SwitchDecision::Status::kKeep, 3, 4), false, config, &state),
            ReevaluationAction::kKeep);
  EXPECT_EQ(state.followed.left_pair, 3);
  EXPECT_EQ(OnReevaluation(proposal, false, config, &state), ReevaluationAction::kNone);
  EXPECT_EQ(OnReevaluation(proposal, false, config, &state), ReevaluationAction::kNone);
  EXPECT_EQ(OnReevaluation(proposal, false, config, &state), ReevaluationAction::kSwitch);
}

TEST(GraspPolicyTest, NoSwitchWhileAGripperCloses) {
  GraspPolicyConfig config;
  config.unreachable_to_switch = 1;
  GraspPolicyState state;
  state.followed = {3, 4};
  const SwitchDecision proposal = Proposal(SwitchDecision::Status::kSwitch, 1, 2);
  EXPECT_EQ(
      OnReevaluation(proposal, Closing(GraspPhase::kGrasp, GraspPhase::kClose), config, &state),
      ReevaluationAction::kNone);
  EXPECT_EQ(state.followed.left_pair, 3);
  EXPECT_TRUE(Closing(GraspPhase::kDone, GraspPhase::kPreCatch));
  EXPECT_FALSE(Closing(GraspPhase::kGrasp, GraspPhase::kTimedOut));
  EXPECT_EQ(OnReevaluation(proposal, false, config, &state), ReevaluationAction::kSwitch);
}

// ---- IK-branch gate -----------------------------------------------------------------

TEST(GraspPolicyTest, AResolvedGraspOnAnotherIkBranchIsNotFollowed) {
  GraspPolicyConfig config;
  config.branch_jump_rad = 0.15;
  config.branch_drift_rad_per_s = 0.5;
  const Eigen::VectorXd last = Eigen::VectorXd::Zero(4);
  Eigen::VectorXd near = last, far = last;
  near[1] = 0.1;
  far[1] = 0.3;
  EXPECT_TRUE(OnFollowedBranch(near, last, 0.0, config));
  EXPECT_FALSE(OnFollowedBranch(far, last, 0.0, config));
  // The allowance grows with the time since the last accepted solution.
  EXPECT_TRUE(OnFollowedBranch(far, last, 0.5, config));
}

// ---- Close --------------------------------------------------------------------------

TEST(GraspPolicyTest, ArmsSettleAtTheirPreCatchPosesBeforeMovingInAndCloseWhenBothHold) {
  GraspPolicyConfig config;
  config.settle_s = 0.2;
  EXPECT_EQ(NextPlannerStep(PlannerState::kServoing, false, 1.0, false, false, config),
            PlannerStep::kNone);
  EXPECT_EQ(NextPlannerStep(PlannerState::kServoing, true, 0.0, false, false, config),
            PlannerStep::kAtPreCatch);
  EXPECT_EQ(NextPlannerStep(PlannerState::kApproachPose, true, 0.1, false, false, config),
            PlannerStep::kNone);
  EXPECT_EQ(NextPlannerStep(PlannerState::kApproachPose, true, 0.2, false, false, config),
            PlannerStep::kGoIn);
  EXPECT_EQ(NextPlannerStep(PlannerState::kGrasping, false, 1.0, true, false, config),
            PlannerStep::kNone);
  EXPECT_EQ(NextPlannerStep(PlannerState::kGrasping, false, 1.0, true, true, config),
            PlannerStep::kClosed);
}

// ---- Retry, re-aim, give up ---------------------------------------------------------

TEST(GraspPolicyTest, AnArmPastItsPreCatchPoseCountsAsThereForTheOther) {
  // A switch that changed only the right arm's pair: the left went on in and
  // closed while the right went back to its new pre-catch pose.
  EXPECT_FALSE(AtOrPastPreCatch(GraspPhase::kPreCatch, false));
  EXPECT_TRUE(AtOrPastPreCatch(GraspPhase::kPreCatch, true));
  EXPECT_TRUE(AtOrPastPreCatch(GraspPhase::kGrasp, false));
  EXPECT_TRUE(AtOrPastPreCatch(GraspPhase::kClose, false));
  EXPECT_TRUE(AtOrPastPreCatch(GraspPhase::kDone, false));
  EXPECT_FALSE(AtOrPastPreCatch(GraspPhase::kTimedOut, false));
  const bool both =
      AtOrPastPreCatch(GraspPhase::kDone, false) && AtOrPastPreCatch(GraspPhase::kPreCatch, true);
  EXPECT_EQ(NextPlannerStep(PlannerState::kServoing, both, 0.0, false, false, GraspPolicyConfig{}),
            PlannerStep::kAtPreCatch);
}

TEST(GraspPolicyTest, AnArmThatTimedOutEndsTheAttempt) {
  AttemptView view;
  view.phase[1] = GraspPhase::kTimedOut;
  const AttemptDecision d = DecideAttempt(view, GraspPolicyState{}, GraspPolicyConfig{});
  EXPECT_EQ(d.action, AttemptAction::kRetry);
  EXPECT_EQ(d.reason, "right arm timed out");
}

TEST(GraspPolicyTest, AnObjectLostTooLongEndsTheAttemptUnlessAGripperCarriesIt) {
  GraspPolicyConfig config;
  config.lost_timeout_s = 2.0;
  AttemptView view;
  view.lost_for_s = 1.5;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kContinue);
  view.lost_for_s = 2.5;
  const AttemptDecision d = DecideAttempt(view, GraspPolicyState{}, config);
  EXPECT_EQ(d.action, AttemptAction::kRetry);
  EXPECT_EQ(d.reason, "object lost for 2.5 s");
  view.one_gripper_carries = true;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kContinue);
}

TEST(GraspPolicyTest, AGripperThatHasBegunClosingFinishesItsCloseBeforeALossEndsTheAttempt) {
  GraspPolicyConfig config;
  config.lost_timeout_s = 2.0;
  AttemptView view;
  view.lost_for_s = 2.05;
  view.phase[0] = GraspPhase::kClose;
  view.phase[1] = GraspPhase::kGrasp;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kContinue);
  view.phase[0] = GraspPhase::kGrasp;
  view.phase[1] = GraspPhase::kClose;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kContinue);
  // The close over (on nothing) and the object still lost: the attempt ends.
  view.phase[1] = GraspPhase::kDone;
  view.lost_for_s = 2.85;
  const AttemptDecision d = DecideAttempt(view, GraspPolicyState{}, config);
  EXPECT_EQ(d.action, AttemptAction::kRetry);
  EXPECT_EQ(d.reason, "object lost for 2.9 s");
}

TEST(GraspPolicyTest, GrippersClosedWithoutHoldingEndTheAttempt) {
  AttemptView view;
  view.phase[0] = view.phase[1] = GraspPhase::kDone;
  view.aperture_m[0] = view.aperture_m[1] = 0.0;
  const AttemptDecision d = DecideAttempt(view, GraspPolicyState{}, GraspPolicyConfig{});
  EXPECT_EQ(d.action, AttemptAction::kRetry);
  EXPECT_THAT(d.reason, HasSubstr("closed without holding the object (left empty at 0 mm"));
  view.holds[0] = view.holds[1] = true;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, GraspPolicyConfig{}).action,
            AttemptAction::kContinue);
}

TEST(GraspPolicyTest, TheFreeArmReaimsWhileTheOtherGripperHolds) {
  GraspPolicyConfig config;
  config.max_reaims = 3;
  AttemptView view;
  view.phase[0] = view.phase[1] = GraspPhase::kDone;
  view.holds[1] = true;  // the right holds, the left closed on nothing
  GraspPolicyState state;
  AttemptDecision d = DecideAttempt(view, state, config);
  EXPECT_EQ(d.action, AttemptAction::kReaim);
  EXPECT_EQ(d.holder, 1);
  // Out of re-aims: the attempt ends.
  state.reaims = 3;
  EXPECT_EQ(DecideAttempt(view, state, config).action, AttemptAction::kRetry);
}

TEST(GraspPolicyTest, AFreeArmWithNoWayToItsTargetReaimsWhileTheOtherCarries) {
  GraspPolicyConfig config;
  config.carried_unreachable_s = 1.0;
  AttemptView view;
  view.phase[0] = GraspPhase::kDone;  // the left holds
  view.holds[0] = true;
  view.one_gripper_carries = true;
  view.phase[1] = GraspPhase::kPreCatch;
  view.unreachable_for_s[1] = 0.9;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kContinue);
  view.unreachable_for_s[1] = 1.0;
  const AttemptDecision d = DecideAttempt(view, GraspPolicyState{}, config);
  EXPECT_EQ(d.action, AttemptAction::kReaim);
  EXPECT_EQ(d.holder, 0);
  // With no gripper holding, an arm with no way in waits for its sequence's timeout.
  view.holds[0] = false;
  view.one_gripper_carries = false;
  view.phase[0] = GraspPhase::kPreCatch;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kContinue);
}

TEST(GraspPolicyTest, WithNoPairForTheFreeArmTheHolderStaysClosedForTheWait) {
  GraspPolicyConfig config;
  config.reaim_wait_s = 2.0;
  AttemptView view;
  view.phase[0] = GraspPhase::kDone;
  view.phase[1] = GraspPhase::kTimedOut;  // the right arm's attempt ended
  view.holds[0] = true;
  view.one_gripper_carries = true;
  view.reaim_unavailable = true;  // its search found no pair
  view.reaim_unavailable_for_s = 0.0;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kWait);
  view.reaim_unavailable_for_s = 2.0;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kWait);
  // The search is due again: it is asked.
  view.reaim_unavailable = false;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, config).action, AttemptAction::kReaim);
  // Still none after the wait: the attempt ends, saying why.
  view.reaim_unavailable = true;
  view.reaim_unavailable_for_s = 2.1;
  const AttemptDecision d = DecideAttempt(view, GraspPolicyState{}, config);
  EXPECT_EQ(d.action, AttemptAction::kRetry);
  EXPECT_THAT(d.reason,
              HasSubstr("the left gripper holds but the right arm found no pair for 2.1 s"));
}

TEST(GraspPolicyTest, TheHoldingGripperFinishesClosingBeforeTheFreeArmReaims) {
  AttemptView view;
  view.phase[0] = GraspPhase::kClose;  // the left holds but is still closing
  view.phase[1] = GraspPhase::kTimedOut;
  view.holds[0] = true;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, GraspPolicyConfig{}).action,
            AttemptAction::kWait);
  // While the free arm still tries, the attempt goes on.
  view.phase[1] = GraspPhase::kGrasp;
  EXPECT_EQ(DecideAttempt(view, GraspPolicyState{}, GraspPolicyConfig{}).action,
            AttemptAction::kContinue);
}

TEST(GraspPolicyTest, TheObjectIsCarriedByTheOnlyGripperHoldingIt) {
  AttemptView view;
  EXPECT_EQ(CarryingGripper(view), -1);
  view.holds[1] = true;
  EXPECT_EQ(CarryingGripper(view), 1);
  view.holds[0] = true;  // both: grasped, not carried by one
  EXPECT_EQ(CarryingGripper(view), -1);
  view.holds[1] = false;
  EXPECT_EQ(CarryingGripper(view), 0);
}

TEST(GraspPolicyTest, PlanningGivesUpAfterItsTimeoutSayingWhy) {
  GraspPolicyConfig config;
  config.planning_timeout_s = 10.0;
  EXPECT_FALSE(PlanningGiveUp(9.9, true, config));
  EXPECT_EQ(PlanningGiveUp(10.1, true, config).value_or(""), "no feasible dual grasp within 10 s");
  EXPECT_EQ(PlanningGiveUp(10.1, false, config).value_or(""),
            "the object was not in view for 10 s to plan again");
}

TEST(GraspPolicyTest, TheFreeArmAimsAtAPairClearOfEdgesThenTheNearest) {
  std::vector<ArmGrasp> candidates(4);
  for (int i = 0; i < 4; ++i) candidates[i].pair = 10 + i;
  candidates[0].cost_rad = 0.1;  // nearest, but near an edge
  candidates[0].clear_of_edges = false;
  candidates[1].cost_rad = 0.5;
  candidates[2].cost_rad = 0.3;
  candidates[3].cost_rad = 0.2;  // near, but too near the holding arm
  const auto clears = [](const ArmGrasp& g) { return g.pair != 13; };
  EXPECT_EQ(RankReaim(candidates, clears), 2);
  EXPECT_EQ(RankReaim(candidates, [](const ArmGrasp&) { return false; }), -1);
  // A pair aimed at in this attempt comes after every other.
  EXPECT_EQ(RankReaim(candidates, clears, {12, 11}), 0);
  EXPECT_EQ(RankReaim(candidates, clears, {10, 11, 12}), 2);
  candidates.resize(1);
  EXPECT_EQ(RankReaim(candidates, clears), 0);  // near an edge is better than none
}

TEST(GraspPolicyTest, ABrieflyLostObjectIsHeldAtItsLastWorldPose) {
  GraspPolicyConfig config;
  config.lost_timeout_s = 2.0;
  EXPECT_TRUE(HoldLastWorldPose(true, false, 1.0, config));
  EXPECT_FALSE(HoldLastWorldPose(true, false, 2.5, config));   // lost too long
  EXPECT_FALSE(HoldLastWorldPose(true, true, -1.0, config));   // in view
  EXPECT_FALSE(HoldLastWorldPose(false, false, 1.0, config));  // never seen within the radius
}

TEST(GraspPolicyTest, AnArmClosesOnlyOnATargetNearItsGraspOnTheObject) {
  GraspPolicyConfig config;
  config.target_on_object_m = 0.01;
  const Eigen::Vector3d grasp_d(0.1, -0.2, 0.45);
  EXPECT_TRUE(TargetOnObject(grasp_d, grasp_d, config));
  EXPECT_TRUE(TargetOnObject(grasp_d + Eigen::Vector3d(0.006, 0.0, -0.006), grasp_d, config));
  EXPECT_FALSE(TargetOnObject(grasp_d + Eigen::Vector3d(0.0, 0.011, 0.0), grasp_d, config));
  config.target_on_object_m = 0.0;
  EXPECT_THROW(config.Validate("mission.yaml", "policy."), ConfigError);
}

TEST(GraspPolicyTest, AnArmAtItsGraspClosesRightAfterTheOther) {
  GraspPolicyConfig config;
  config.close_together_m = 0.01;
  config.close_wait_s = 1.0;
  EXPECT_FALSE(MayClose(GraspPhase::kPreCatch, 0.0, 0.5, config));  // the other not in yet
  EXPECT_FALSE(MayClose(GraspPhase::kGrasp, 0.02, 0.5, config));    // on its way in
  EXPECT_TRUE(MayClose(GraspPhase::kGrasp, 0.008, 0.0, config));    // near its grasp
  EXPECT_TRUE(MayClose(GraspPhase::kClose, 0.05, 0.0, config));
  EXPECT_TRUE(MayClose(GraspPhase::kDone, 0.05, 0.0, config));  // it holds: a re-aim
  EXPECT_TRUE(MayClose(GraspPhase::kTimedOut, 0.05, 0.0, config));
  EXPECT_TRUE(MayClose(GraspPhase::kGrasp, 0.02, 1.0, config));  // waited long enough
  config.close_together_m = 0.0;
  EXPECT_TRUE(MayClose(GraspPhase::kPreCatch, 0.2, 0.0, config));  // off: closes on arrival
  config.close_together_m = 0.3;
  EXPECT_THROW(config.Validate("mission.yaml", "policy."), ConfigError);
}

TEST(GraspPolicyConfigTest, ABadValueNamesTheFileKeyAndBound) {
  GraspPolicyConfig config;
  EXPECT_NO_THROW(config.Validate("mission.yaml", "policy."));
  config.unreachable_to_switch = 0;
  try {
    config.Validate("mission.yaml", "policy.");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mission.yaml: policy.unreachable_to_switch"));
    EXPECT_THAT(e.what(), HasSubstr("1"));
  }
}

TEST(GraspPolicyConfigTest, ANegativeHeldCarryNamesItsKey) {
  GraspPolicyConfig config;
  config.held_max_carry_m = -0.01;
  try {
    config.Validate("mission.yaml", "policy.");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mission.yaml: policy.held_max_carry_m"));
  }
}

TEST(GraspPolicyTest, AHeldObjectMovesOnWithItsVelocityTrustedLessWithTime) {
  GraspPolicyConfig config;
  config.held_velocity_trust_s = 1.0;
  config.held_min_speed_mps = 0.01;
  config.held_max_carry_m = 0.05;
  const Eigen::Vector3d v(0.03, 0.0, 0.0);  // crawling at 3 cm/s
  // Early on almost the full velocity: 0.1 s moves it about 3 mm.
  EXPECT_NEAR(HeldWorldDisplacement(v, 0.1, config).x(), 0.03 * (1.0 - std::exp(-0.1)), 1e-12);
  EXPECT_GT(HeldWorldDisplacement(v, 0.1, config).x(), 0.0028);
  // Later less per second: 2 s moves it 26 mm, not 60 mm.
  EXPECT_NEAR(HeldWorldDisplacement(v, 2.0, config).x(), 0.03 * (1.0 - std::exp(-2.0)), 1e-12);
  EXPECT_DOUBLE_EQ(HeldWorldDisplacement(v, 2.0, config).y(), 0.0);
  // Never more than one trust time's worth, nor beyond the bound.
  EXPECT_LT(HeldWorldDisplacement(v, 60.0, config).norm(), 0.03 + 1e-12);
  EXPECT_NEAR(HeldWorldDisplacement(Eigen::Vector3d(0.0, -0.3, 0.0), 5.0, config).y(), -0.05,
              1e-12);
}

TEST(GraspPolicyTest, AStillOrUnseenForNoTimeObjectIsHeldStill) {
  GraspPolicyConfig config;
  config.held_min_speed_mps = 0.01;
  EXPECT_TRUE(HeldWorldDisplacement(Eigen::Vector3d(0.005, 0.005, 0.0), 1.0, config).isZero());
  EXPECT_TRUE(HeldWorldDisplacement(Eigen::Vector3d(0.03, 0.0, 0.0), 0.0, config).isZero());
  EXPECT_TRUE(HeldWorldDisplacement(Eigen::Vector3d(0.03, 0.0, 0.0), -0.1, config).isZero());
  config.held_velocity_trust_s = 0.0;  // off: held at the last world pose
  EXPECT_TRUE(HeldWorldDisplacement(Eigen::Vector3d(0.03, 0.0, 0.0), 1.0, config).isZero());
}

}  // namespace
}  // namespace aerograsp
