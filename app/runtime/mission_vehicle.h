// The mission's vehicle legs: take off, fly to the approach waypoint, hover
// there until the object is found, track it (the body's grasp point over the
// object, kept within the geofence around the waypoint), search again when it
// is lost, lift, fly home and land. Feeds the vehicle and global state
// machines and sends the autopilot its position setpoints.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <string>

#include "app/runtime/mission_config.h"
#include "hardware/autopilot.h"
#include "mission/state_machines.h"

namespace aerograsp {

/// The tracking setpoint: the body where the object sits at grasp_dto_m under
/// it (yaw held at yaw_rad) once the vehicle gets there, but never farther
/// than tracking_radius_m from the approach waypoint (the geofence). The
/// object's filtered position object_w_m lags it by object_filter_s and the
/// vehicle lags its setpoint by vehicle_lag_s: the setpoint leads by the
/// object's velocity object_v_w_mps times both.
Eigen::Vector3d TrackingSetpoint(const Eigen::Vector3d& object_w_m,
                                 const Eigen::Vector3d& object_v_w_mps,
                                 const MissionConfig& config);

/// True when an object at object_w_m is beyond the tracking radius (plus the
/// grasp point's offset) from the approach waypoint: it is not followed.
bool BeyondTrackingRadius(const Eigen::Vector3d& object_w_m, const MissionConfig& config);

/// What the legs need to know of the rest of the mission each cycle.
struct VehicleView {
  bool object_found = false;         ///< vision state found
  double lost_for_s = -1.0;          ///< object out of view this long; < 0: in view
  bool one_gripper_carries = false;  ///< a re-aim is under way: the vehicle does not search
  /// The vehicle does not chase what it carries, nor search for it.
  bool a_gripper_holds = false;
  bool have_object_w = false;  ///< the object was seen within the tracking radius
  Eigen::Vector3d object_w_m = Eigen::Vector3d::Zero();  ///< its filtered position
  /// Its estimated velocity (m/s, in w) while in view; zero when lost.
  Eigen::Vector3d object_v_w_mps = Eigen::Vector3d::Zero();
};

class VehicleLegs {
 public:
  /// `emergency` stops the mission with a cause; `log` writes one line.
  VehicleLegs(const MissionConfig& config, Autopilot* autopilot, GlobalMachine* global,
              VehicleMachine* vehicle, std::function<void(const std::string&)> emergency,
              std::function<void(const std::string&)> log);
  /// One cycle at t_s. True when the vehicle tracks the object this cycle (the
  /// grasp may then be planned).
  bool Step(double t_s, const VehicleView& view);

 private:
  enum class Leg { kApproach, kTrack, kLift, kHome };
  void GoTo(double t_s, const Eigen::Vector3d& w, Leg leg, const std::string& name);

  const MissionConfig& config_;
  Autopilot* autopilot_;
  GlobalMachine* global_;
  VehicleMachine* vehicle_;
  std::function<void(const std::string&)> emergency_, log_;
  Eigen::Vector3d waypoint_w_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d setpoint_w_ = Eigen::Vector3d::Zero();
  Leg leg_ = Leg::kApproach;
  double hover_since_s_ = -1.0;
  double next_setpoint_s_ = 0.0;
};

}  // namespace aerograsp
