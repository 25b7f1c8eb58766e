#include <gtest/gtest.h>

#include <vector>

#include "mission/state_machines.h"

namespace aerograsp {
namespace {

struct Sink {
  std::vector<StateTransition> log;
  TransitionSink fn() {
    return [this](const StateTransition& t) { log.push_back(t); };
  }
};

TEST(GlobalMachineTest, RunsApproachGraspHomeAndLogsEachCause) {
  Sink sink;
  GlobalMachine g(sink.fn());
  EXPECT_FALSE(g.Found(0.5, true));  // not started: refused, nothing logged
  EXPECT_TRUE(sink.log.empty());
  EXPECT_TRUE(g.Start(1.0));
  EXPECT_FALSE(g.Found(2.0, false));  // found away from the waypoint: keep approaching
  EXPECT_EQ(g.state(), GlobalState::kApproaching);
  EXPECT_TRUE(g.Found(3.0, true));
  EXPECT_TRUE(g.Grasped(4.0));
  EXPECT_TRUE(g.Landed(5.0));
  EXPECT_EQ(g.state(), GlobalState::kDone);
  EXPECT_FALSE(g.failed());
  ASSERT_EQ(sink.log.size(), 4u);
  EXPECT_EQ(sink.log[1].machine, "global");
  EXPECT_EQ(sink.log[1].from, "approaching");
  EXPECT_EQ(sink.log[1].to, "grasping");
  EXPECT_DOUBLE_EQ(sink.log[1].t_s, 3.0);
  EXPECT_NE(sink.log[1].cause.find("found"), std::string::npos);
  EXPECT_FALSE(g.Emergency(6.0, "late"));  // done is final
}

TEST(GlobalMachineTest, GivingUpHomesWithTheFailureAndEmergencyIsLatched) {
  GlobalMachine g;
  g.Start(0.0);
  g.Found(1.0, true);
  EXPECT_TRUE(g.GiveUp(2.0, "no grasp"));
  EXPECT_EQ(g.state(), GlobalState::kHoming);
  EXPECT_TRUE(g.failed());
  EXPECT_EQ(g.failure(), "no grasp");
  EXPECT_FALSE(g.GiveUp(2.5, "again"));
  EXPECT_TRUE(g.Emergency(3.0, "link lost"));
  EXPECT_EQ(g.state(), GlobalState::kAborted);
  EXPECT_EQ(g.failure(), "link lost");
  EXPECT_FALSE(g.Landed(4.0));
  EXPECT_FALSE(g.Emergency(4.0, "twice"));
  EXPECT_EQ(g.state(), GlobalState::kAborted);
}

TEST(VehicleMachineTest, FollowsThePaperSixStates) {
  Sink sink;
  VehicleMachine v(sink.fn());
  EXPECT_FALSE(v.GoTo(0.0, "too early"));
  EXPECT_TRUE(v.TakeOff(0.0));
  EXPECT_TRUE(v.Airborne(2.0));
  EXPECT_TRUE(v.GoTo(2.0, "approach"));
  EXPECT_FALSE(v.Found(2.5));  // found while flying to the waypoint: not yet tracking
  EXPECT_TRUE(v.Arrived(4.0));
  EXPECT_TRUE(v.Found(4.1));
  EXPECT_EQ(v.state(), VehicleMode::kTracking);
  EXPECT_TRUE(v.Lost(5.0));
  EXPECT_EQ(v.state(), VehicleMode::kHover);
  EXPECT_TRUE(v.Found(5.5));
  EXPECT_TRUE(v.GoTo(6.0, "lift"));
  EXPECT_TRUE(v.Land(7.0, "home"));
  EXPECT_FALSE(v.TakeOff(7.5));
  EXPECT_TRUE(v.Landed(9.0));
  EXPECT_EQ(v.state(), VehicleMode::kIdle);
  EXPECT_EQ(sink.log.size(), 10u);
  EXPECT_EQ(sink.log.back().cause, "landed");
  EXPECT_DOUBLE_EQ(v.TimeIn(10.0), 1.0);
}

TEST(VisionMachineTest, SignalsFoundAndLostOnlyOnChanges) {
  VisionMachine v;
  EXPECT_EQ(v.Update(0.0, false, "nothing"), VisionSignal::kNone);
  EXPECT_EQ(v.state(), VisionState::kSearching);
  EXPECT_EQ(v.Update(0.1, true, "pose"), VisionSignal::kFound);
  EXPECT_EQ(v.Update(0.2, true, "pose"), VisionSignal::kNone);
  EXPECT_EQ(v.Update(0.3, false, "gone"), VisionSignal::kLost);
  EXPECT_EQ(v.state(), VisionState::kLost);
  EXPECT_EQ(v.Update(0.4, false, "gone"), VisionSignal::kNone);
  EXPECT_EQ(v.Update(0.5, true, "back"), VisionSignal::kFound);
}

TEST(PlannerMachineTest, GoesInOnlyFromTheApproachPoseAndGivesUpAfterMaxAttempts) {
  Sink sink;
  PlannerMachine p(2, sink.fn());
  EXPECT_FALSE(p.Planned(0.0, "no"));
  EXPECT_TRUE(p.Start(0.0));
  EXPECT_FALSE(p.GoIn(0.1));  // not at the pre-catch poses yet
  EXPECT_TRUE(p.Planned(0.2, "pair 1 2"));
  EXPECT_FALSE(p.Closed(0.3));
  EXPECT_TRUE(p.AtPreCatch(1.0));
  EXPECT_TRUE(p.Switched(1.1, "pair became unreachable"));
  EXPECT_EQ(p.state(), PlannerState::kServoing);
  EXPECT_TRUE(p.Retry(2.0, "left arm timed out"));
  EXPECT_EQ(p.state(), PlannerState::kPlanning);
  EXPECT_EQ(p.attempts(), 1);
  EXPECT_NE(sink.log.back().cause.find("attempt 1 of 2"), std::string::npos);
  EXPECT_TRUE(p.Planned(2.1, "pair 3 4"));
  EXPECT_TRUE(p.AtPreCatch(3.0));
  EXPECT_TRUE(p.GoIn(3.2));
  EXPECT_TRUE(p.Retry(4.0, "object lost"));
  EXPECT_EQ(p.state(), PlannerState::kFailed);
  EXPECT_FALSE(p.Retry(5.0, "again"));
}

TEST(PlannerMachineTest, ClosesFromGrasping) {
  PlannerMachine p(3);
  p.Start(0.0);
  p.Planned(0.0, "pair");
  p.AtPreCatch(1.0);
  p.GoIn(1.2);
  EXPECT_TRUE(p.Closed(2.0));
  EXPECT_EQ(p.state(), PlannerState::kGrasped);
  EXPECT_FALSE(p.Retry(2.5, "too late"));
}

TEST(ArmsMachineTest, EmergencyStopIsLatchedAndBlocksCommands) {
  ArmsMachine arms;
  EXPECT_FALSE(arms.commands_allowed());
  EXPECT_TRUE(arms.Move(0.0, "servo"));
  EXPECT_TRUE(arms.commands_allowed());
  EXPECT_TRUE(arms.Hold(1.0, "grasped"));
  EXPECT_FALSE(arms.commands_allowed());
  EXPECT_TRUE(arms.Move(2.0, "again"));
  EXPECT_TRUE(arms.EmergencyStop(3.0, "servo bus silent"));
  EXPECT_FALSE(arms.commands_allowed());
  EXPECT_FALSE(arms.Move(4.0, "resume"));
  EXPECT_FALSE(arms.Hold(4.0, "hold"));
  EXPECT_FALSE(arms.EmergencyStop(5.0, "twice"));
  EXPECT_EQ(arms.state(), ArmsState::kEmergencyStop);
}

}  // namespace
}  // namespace aerograsp
