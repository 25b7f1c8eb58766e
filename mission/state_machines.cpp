#include "mission/state_machines.h"

namespace aerograsp {

const char* StateName(GlobalState state) {
  switch (state) {
    case GlobalState::kIdle:
      return "idle";
    case GlobalState::kApproaching:
      return "approaching";
    case GlobalState::kGrasping:
      return "grasping";
    case GlobalState::kHoming:
      return "homing";
    case GlobalState::kDone:
      return "done";
    case GlobalState::kAborted:
      return "aborted";
  }
  return "?";
}

bool GlobalMachine::Start(double now_s) {
  if (state() != GlobalState::kIdle) return false;
  Go(GlobalState::kApproaching, now_s, "start");
  return true;
}

bool GlobalMachine::Found(double now_s, bool at_waypoint) {
  if (state() != GlobalState::kApproaching || !at_waypoint) return false;
  Go(GlobalState::kGrasping, now_s, "found: the object is in view at the approach waypoint");
  return true;
}

bool GlobalMachine::Grasped(double now_s) {
  if (state() != GlobalState::kGrasping) return false;
  Go(GlobalState::kHoming, now_s, "grasped: both grippers hold the object");
  return true;
}

bool GlobalMachine::GiveUp(double now_s, const std::string& cause) {
  if (state() != GlobalState::kApproaching && state() != GlobalState::kGrasping) return false;
  failed_ = true;
  failure_ = cause;
  Go(GlobalState::kHoming, now_s, "giving up: " + cause);
  return true;
}

bool GlobalMachine::Landed(double now_s) {
  if (state() != GlobalState::kHoming) return false;
  Go(GlobalState::kDone, now_s, "landed");
  return true;
}

bool GlobalMachine::Emergency(double now_s, const std::string& cause) {
  if (state() == GlobalState::kDone || state() == GlobalState::kAborted) return false;
  failed_ = true;
  failure_ = cause;
  Go(GlobalState::kAborted, now_s, "emergency: " + cause);
  return true;
}

const char* StateName(VehicleMode state) {
  switch (state) {
    case VehicleMode::kIdle:
      return "idle";
    case VehicleMode::kTakeOff:
      return "take-off";
    case VehicleMode::kHover:
      return "hover";
    case VehicleMode::kWaypoint:
      return "waypoint";
    case VehicleMode::kTracking:
      return "tracking";
    case VehicleMode::kLanding:
      return "landing";
  }
  return "?";
}

bool VehicleMachine::TakeOff(double now_s) {
  if (state() != VehicleMode::kIdle) return false;
  Go(VehicleMode::kTakeOff, now_s, "take_off");
  return true;
}

bool VehicleMachine::Airborne(double now_s) {
  if (state() != VehicleMode::kTakeOff) return false;
  Go(VehicleMode::kHover, now_s, "airborne: take-off altitude reached");
  return true;
}

bool VehicleMachine::GoTo(double now_s, const std::string& cause) {
  if (state() != VehicleMode::kHover && state() != VehicleMode::kTracking) return false;
  Go(VehicleMode::kWaypoint, now_s, cause);
  return true;
}

bool VehicleMachine::Arrived(double now_s) {
  if (state() != VehicleMode::kWaypoint) return false;
  Go(VehicleMode::kHover, now_s, "arrived at the waypoint");
  return true;
}

bool VehicleMachine::Found(double now_s) {
  if (state() != VehicleMode::kHover) return false;
  Go(VehicleMode::kTracking, now_s, "found: holding the object in the arms' workspace");
  return true;
}

bool VehicleMachine::Lost(double now_s) {
  if (state() != VehicleMode::kTracking) return false;
  Go(VehicleMode::kHover, now_s, "lost: holding position");
  return true;
}

bool VehicleMachine::Land(double now_s, const std::string& cause) {
  if (state() != VehicleMode::kHover && state() != VehicleMode::kWaypoint &&
      state() != VehicleMode::kTracking) {
    return false;
  }
  Go(VehicleMode::kLanding, now_s, cause);
  return true;
}

bool VehicleMachine::Landed(double now_s) {
  if (state() != VehicleMode::kLanding) return false;
  Go(VehicleMode::kIdle, now_s, "landed");
  return true;
}

const char* StateName(VisionState state) {
  switch (state) {
    case VisionState::kSearching:
      return "searching";
    case VisionState::kFound:
      return "found";
    case VisionState::kLost:
      return "lost";
  }
  return "?";
}

VisionSignal VisionMachine::Update(double now_s, bool found, const std::string& cause) {
  if (found && state() != VisionState::kFound) {
    Go(VisionState::kFound, now_s, cause);
    return VisionSignal::kFound;
  }
  if (!found && state() == VisionState::kFound) {
    Go(VisionState::kLost, now_s, cause);
    return VisionSignal::kLost;
  }
  return VisionSignal::kNone;
}

const char* StateName(PlannerState state) {
  switch (state) {
    case PlannerState::kIdle:
      return "idle";
    case PlannerState::kPlanning:
      return "planning";
    case PlannerState::kServoing:
      return "servoing";
    case PlannerState::kApproachPose:
      return "approach pose";
    case PlannerState::kGrasping:
      return "grasping";
    case PlannerState::kGrasped:
      return "grasped";
    case PlannerState::kFailed:
      return "failed";
  }
  return "?";
}

bool PlannerMachine::Start(double now_s) {
  if (state() != PlannerState::kIdle) return false;
  Go(PlannerState::kPlanning, now_s, "near: the object is within the arms' reach");
  return true;
}

bool PlannerMachine::Planned(double now_s, const std::string& cause) {
  if (state() != PlannerState::kPlanning) return false;
  Go(PlannerState::kServoing, now_s, cause);
  return true;
}

bool PlannerMachine::AtPreCatch(double now_s) {
  if (state() != PlannerState::kServoing) return false;
  Go(PlannerState::kApproachPose, now_s, "both arms at their pre-catch poses");
  return true;
}

bool PlannerMachine::GoIn(double now_s) {
  if (state() != PlannerState::kApproachPose) return false;
  Go(PlannerState::kGrasping, now_s, "approach pose settled: moving in");
  return true;
}

bool PlannerMachine::Closed(double now_s) {
  if (state() != PlannerState::kGrasping) return false;
  Go(PlannerState::kGrasped, now_s, "both grippers hold the object");
  return true;
}

bool PlannerMachine::Switched(double now_s, const std::string& cause) {
  if (state() != PlannerState::kServoing && state() != PlannerState::kApproachPose &&
      state() != PlannerState::kGrasping) {
    return false;
  }
  Go(PlannerState::kServoing, now_s, cause);
  return true;
}

bool PlannerMachine::Retry(double now_s, const std::string& cause) {
  if (state() != PlannerState::kServoing && state() != PlannerState::kApproachPose &&
      state() != PlannerState::kGrasping) {
    return false;
  }
  ++attempts_;
  if (attempts_ >= max_attempts_) {
    Go(PlannerState::kFailed, now_s,
       cause + " (attempt " + std::to_string(attempts_) + " of " + std::to_string(max_attempts_) +
           ": giving up)");
  } else {
    Go(PlannerState::kPlanning, now_s,
       cause + " (attempt " + std::to_string(attempts_) + " of " + std::to_string(max_attempts_) +
           ": planning again)");
  }
  return true;
}

const char* StateName(ArmsState state) {
  switch (state) {
    case ArmsState::kIdle:
      return "idle";
    case ArmsState::kMoving:
      return "moving";
    case ArmsState::kHolding:
      return "holding";
    case ArmsState::kEmergencyStop:
      return "emergency stop";
  }
  return "?";
}

bool ArmsMachine::Move(double now_s, const std::string& cause) {
  if (state() != ArmsState::kIdle && state() != ArmsState::kHolding) return false;
  Go(ArmsState::kMoving, now_s, cause);
  return true;
}

bool ArmsMachine::Hold(double now_s, const std::string& cause) {
  if (state() != ArmsState::kIdle && state() != ArmsState::kMoving) return false;
  Go(ArmsState::kHolding, now_s, cause);
  return true;
}

bool ArmsMachine::EmergencyStop(double now_s, const std::string& cause) {
  if (state() == ArmsState::kEmergencyStop) return false;
  Go(ArmsState::kEmergencyStop, now_s, cause);
  return true;
}

}  // namespace aerograsp
