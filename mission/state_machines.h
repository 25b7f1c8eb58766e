// The mission's five state machines (paper Sect. 5, Figs. 6 and 7): global,
// vehicle, vision, grasp planner and arms controller. Each is a small class
// with explicit states and one method per signal; a signal that does not apply
// in the present state is refused (returns false) and changes nothing. Every
// transition goes to the sink with the machine's name, both states and its
// cause. Pure logic: no clock, threads or devices; the runner
// (app/runtime/mission_runner.h) feeds them and acts on their states.
#pragma once

#include <functional>
#include <string>

namespace aerograsp {

struct StateTransition {
  double t_s = 0.0;
  std::string machine;
  std::string from, to;
  std::string cause;
};
using TransitionSink = std::function<void(const StateTransition&)>;

/// Shared bookkeeping: the state, when it was entered, and logged transitions.
template <typename State>
class StateMachine {
 public:
  State state() const { return state_; }
  double entered_s() const { return entered_s_; }
  /// Seconds spent in the present state at now_s.
  double TimeIn(double now_s) const { return now_s - entered_s_; }

 protected:
  StateMachine(std::string name, State initial, TransitionSink sink)
      : name_(std::move(name)), state_(initial), sink_(std::move(sink)) {}
  /// Enters `to` (also when it is the present state: a re-entry restarts its clock).
  void Go(State to, double now_s, const std::string& cause) {
    if (sink_) sink_({now_s, name_, StateName(state_), StateName(to), cause});
    state_ = to;
    entered_s_ = now_s;
  }

 private:
  std::string name_;
  State state_;
  double entered_s_ = 0.0;
  TransitionSink sink_;
};

// ---- Global (Fig. 6a) -------------------------------------------------------
enum class GlobalState { kIdle, kApproaching, kGrasping, kHoming, kDone, kAborted };
const char* StateName(GlobalState state);

class GlobalMachine : public StateMachine<GlobalState> {
 public:
  explicit GlobalMachine(TransitionSink sink = {})
      : StateMachine("global", GlobalState::kIdle, std::move(sink)) {}
  /// idle -> approaching (the vehicle is then told to take off, then to fly to the waypoint).
  bool Start(double now_s);
  /// approaching -> grasping: the object is found with the vehicle at the waypoint.
  bool Found(double now_s, bool at_waypoint);
  /// grasping -> homing with the object.
  bool Grasped(double now_s);
  /// approaching or grasping -> homing without the object (the mission failed: `cause`).
  bool GiveUp(double now_s, const std::string& cause);
  /// homing -> done.
  bool Landed(double now_s);
  /// any state but done -> aborted (latched): arms stopped, vehicle holding.
  bool Emergency(double now_s, const std::string& cause);
  /// True once GiveUp or Emergency was signalled.
  bool failed() const { return failed_; }
  const std::string& failure() const { return failure_; }

 private:
  bool failed_ = false;
  std::string failure_;
};

// ---- Vehicle (Fig. 6b) ------------------------------------------------------
enum class VehicleMode { kIdle, kTakeOff, kHover, kWaypoint, kTracking, kLanding };
const char* StateName(VehicleMode state);

class VehicleMachine : public StateMachine<VehicleMode> {
 public:
  explicit VehicleMachine(TransitionSink sink = {})
      : StateMachine("vehicle", VehicleMode::kIdle, std::move(sink)) {}
  bool TakeOff(double now_s);   ///< idle -> take-off
  bool Airborne(double now_s);  ///< take-off -> hover
  /// hover or tracking -> waypoint (`cause` names the waypoint).
  bool GoTo(double now_s, const std::string& cause);
  bool Arrived(double now_s);                         ///< waypoint -> hover
  bool Found(double now_s);                           ///< hover -> tracking
  bool Lost(double now_s);                            ///< tracking -> hover
  bool Land(double now_s, const std::string& cause);  ///< hover, waypoint or tracking -> landing
  bool Landed(double now_s);                          ///< landing -> idle
};

// ---- Vision (Fig. 7a) -------------------------------------------------------
enum class VisionState { kSearching, kFound, kLost };
const char* StateName(VisionState state);

/// What a vision update means for the other machines.
enum class VisionSignal { kNone, kFound, kLost };

class VisionMachine : public StateMachine<VisionState> {
 public:
  explicit VisionMachine(TransitionSink sink = {})
      : StateMachine("vision", VisionState::kSearching, std::move(sink)) {}
  /// One perception result: `found` is the tracker's found / lost decision.
  /// searching or lost -> found gives kFound; found -> lost gives kLost.
  VisionSignal Update(double now_s, bool found, const std::string& cause);
};

// ---- Grasp planner (Fig. 7b) ------------------------------------------------
enum class PlannerState {
  kIdle,
  kPlanning,
  kServoing,
  kApproachPose,
  kGrasping,
  kGrasped,
  kFailed
};
const char* StateName(PlannerState state);

class PlannerMachine : public StateMachine<PlannerState> {
 public:
  /// `max_attempts`: plans that may end in a failed approach before kFailed, >= 1.
  explicit PlannerMachine(int max_attempts, TransitionSink sink = {})
      : StateMachine("planner", PlannerState::kIdle, std::move(sink)),
        max_attempts_(max_attempts) {}
  bool Start(double now_s);  ///< idle -> planning
  /// planning -> servoing: a dual grasp was chosen (`cause` names it).
  bool Planned(double now_s, const std::string& cause);
  bool AtPreCatch(double now_s);  ///< servoing -> approach pose: both arms at their pre-catch poses
  bool GoIn(double now_s);        ///< approach pose -> grasping: the arms move in and close
  bool Closed(double now_s);      ///< grasping -> grasped: both grippers hold the object
  /// servoing, approach pose or grasping -> servoing: the followed grasp became
  /// unreachable and re-evaluation chose another (`cause`: which and why).
  bool Switched(double now_s, const std::string& cause);
  /// servoing, approach pose or grasping -> planning again (`cause`: a timeout,
  /// an unreachable grasp, the object lost); after max_attempts of them -> failed.
  bool Retry(double now_s, const std::string& cause);
  int attempts() const { return attempts_; }

 private:
  int max_attempts_;
  int attempts_ = 0;
};

// ---- Arms controller (Fig. 7c) ----------------------------------------------
enum class ArmsState { kIdle, kMoving, kHolding, kEmergencyStop };
const char* StateName(ArmsState state);

class ArmsMachine : public StateMachine<ArmsState> {
 public:
  explicit ArmsMachine(TransitionSink sink = {})
      : StateMachine("arms", ArmsState::kIdle, std::move(sink)) {}
  bool Move(double now_s,
            const std::string& cause);  ///< idle or holding -> moving (servo commands pass)
  bool Hold(double now_s,
            const std::string& cause);  ///< idle or moving -> holding (targets frozen)
  /// Any state -> emergency stop (latched: every later signal is refused).
  bool EmergencyStop(double now_s, const std::string& cause);
  /// True when joint commands may reach the arms.
  bool commands_allowed() const { return state() == ArmsState::kMoving; }
};

}  // namespace aerograsp
