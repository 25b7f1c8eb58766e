#include "app/runtime/mission_vehicle.h"

#include <fmt/format.h>

#include <cmath>

namespace aerograsp {

Eigen::Vector3d TrackingSetpoint(const Eigen::Vector3d& object_w_m,
                                 const Eigen::Vector3d& object_v_w_mps,
                                 const MissionConfig& config) {
  const Eigen::Matrix3d wRyaw =
      Eigen::AngleAxisd(config.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d lead_m = (config.object_filter_s + config.vehicle_lag_s) * object_v_w_mps;
  const Eigen::Vector3d wanted = object_w_m + lead_m - wRyaw * config.grasp_dto_m;
  const Eigen::Vector3d off = wanted - config.approach_w_m;
  return off.norm() <= config.tracking_radius_m
             ? wanted
             : Eigen::Vector3d(config.approach_w_m + off.normalized() * config.tracking_radius_m);
}

bool BeyondTrackingRadius(const Eigen::Vector3d& object_w_m, const MissionConfig& config) {
  return (object_w_m - config.approach_w_m).norm() >
         config.tracking_radius_m + config.grasp_dto_m.norm();
}

VehicleLegs::VehicleLegs(const MissionConfig& config, Autopilot* autopilot, GlobalMachine* global,
                         VehicleMachine* vehicle, std::function<void(const std::string&)> emergency,
                         std::function<void(const std::string&)> log)
    : config_(config),
      autopilot_(autopilot),
      global_(global),
      vehicle_(vehicle),
      emergency_(std::move(emergency)),
      log_(std::move(log)) {}

void VehicleLegs::GoTo(double t_s, const Eigen::Vector3d& w, Leg leg, const std::string& name) {
  waypoint_w_ = w;
  leg_ = leg;
  setpoint_w_ = w;
  vehicle_->GoTo(t_s,
                 fmt::format("{}: waypoint [{:.2f}, {:.2f}, {:.2f}] m", name, w.x(), w.y(), w.z()));
}

bool VehicleLegs::Step(double t, const VehicleView& view) {
  // A lost link is a device fault (app/runtime/mission_health.h): the runner
  // stops the mission before this step.
  const VehicleState vs = autopilot_->State();
  const Eigen::Vector3d p_w = vs.wMd.translation();
  const GlobalState g = global_->state();
  if (g == GlobalState::kAborted || g == GlobalState::kDone) return false;

  bool tracking = false;
  switch (vehicle_->state()) {
    case VehicleMode::kIdle:
      if (g == GlobalState::kApproaching) {
        CommandAck ack = autopilot_->Arm();
        if (ack.accepted) ack = autopilot_->Takeoff(config_.takeoff_altitude_m);
        if (!ack.accepted) {
          // Still on the ground: there is nothing to fly home, the mission ends here.
          global_->GiveUp(t, "the autopilot refused to take off: " + ack.reason);
          global_->Landed(t);
          return false;
        }
        vehicle_->TakeOff(t);
      }
      break;
    case VehicleMode::kTakeOff:
      if (vs.mode == FlightMode::kHold &&
          std::abs(-p_w.z() - config_.takeoff_altitude_m) < config_.arrive_tolerance_m) {
        vehicle_->Airborne(t);
        if (g == GlobalState::kApproaching) {
          GoTo(t, config_.approach_w_m, Leg::kApproach, "approach");
        } else {
          GoTo(t, Eigen::Vector3d(0.0, 0.0, p_w.z()), Leg::kHome, "home");
        }
      }
      break;
    case VehicleMode::kWaypoint:
      if ((p_w - waypoint_w_).norm() < config_.arrive_tolerance_m) {
        vehicle_->Arrived(t);
        hover_since_s_ = t;
        if (leg_ == Leg::kLift) {
          GoTo(t, Eigen::Vector3d(0.0, 0.0, waypoint_w_.z()), Leg::kHome, "home");
        } else if (leg_ == Leg::kHome) {
          const CommandAck ack = autopilot_->Land();
          if (!ack.accepted) {
            emergency_("the autopilot refused to land: " + ack.reason);
            return false;
          }
          vehicle_->Land(t, "over the take-off point");
        }
      }
      break;
    case VehicleMode::kHover:
      if (g == GlobalState::kHoming) {
        GoTo(t, p_w - Eigen::Vector3d(0.0, 0.0, config_.lift_m), Leg::kLift, "lift");
      } else if (view.object_found) {
        if (g == GlobalState::kApproaching) global_->Found(t, leg_ == Leg::kApproach);
        if (global_->state() == GlobalState::kGrasping && vehicle_->Found(t)) leg_ = Leg::kTrack;
      } else if (g == GlobalState::kGrasping && view.lost_for_s > config_.policy.lost_timeout_s &&
                 leg_ == Leg::kTrack && !view.one_gripper_carries && !view.a_gripper_holds) {
        // (Not while a gripper holds it: the flight would drag it away.)
        GoTo(t, config_.approach_w_m, Leg::kApproach, "search again");
      } else if ((g == GlobalState::kApproaching ||
                  (g == GlobalState::kGrasping && leg_ == Leg::kApproach)) &&
                 t - hover_since_s_ > config_.search_timeout_s) {
        global_->GiveUp(t, fmt::format("the object was {} in {:.0f} s at the approach waypoint",
                                       g == GlobalState::kApproaching ? "not found"
                                                                      : "lost and not found again",
                                       config_.search_timeout_s));
      }
      break;
    case VehicleMode::kTracking:
      if (g == GlobalState::kHoming) {
        GoTo(t, p_w - Eigen::Vector3d(0.0, 0.0, config_.lift_m), Leg::kLift, "lift");
        break;
      }
      // An object a gripper holds moves with the vehicle: tracking it, the
      // vehicle would chase what it carries (and drag it off its pipe while
      // the other arm still tries).
      if (view.have_object_w && !view.a_gripper_holds)
        setpoint_w_ = TrackingSetpoint(view.object_w_m, view.object_v_w_mps, config_);
      tracking = true;
      break;
    case VehicleMode::kLanding:
      if (vs.mode == FlightMode::kLanded || vs.mode == FlightMode::kDisarmed) {
        vehicle_->Landed(t);
        global_->Landed(t);
      }
      break;
  }
  // Setpoints while the companion flies the vehicle.
  const VehicleMode m = vehicle_->state();
  if ((m == VehicleMode::kWaypoint || m == VehicleMode::kHover || m == VehicleMode::kTracking) &&
      t + 1e-9 >= next_setpoint_s_) {
    next_setpoint_s_ = t + 1.0 / config_.setpoint_rate_hz;
    const CommandAck ack = autopilot_->SetPositionTarget(setpoint_w_, config_.yaw_rad);
    if (!ack.accepted) log_("autopilot refused the setpoint: " + ack.reason);
  }
  return tracking;
}

}  // namespace aerograsp
