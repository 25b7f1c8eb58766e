// The autopilot as the mission sees it: state, pose and velocity of the
// vehicle, arm / take-off / land / hold, and position setpoints. World frame
// w is NED (core/frames.h) with its origin at the take-off point. Backends:
// the simulator and PX4 over MAVLink.
#pragma once

#include <Eigen/Geometry>
#include <string>

namespace aerograsp {

enum class FlightMode {
  kDisarmed,   ///< on the ground, motors off
  kLanded,     ///< armed on the ground
  kTakingOff,  ///< climbing to the take-off altitude
  kHold,       ///< hovering at a fixed point (PX4 Hold / Loiter)
  kOffboard,   ///< following the companion's position setpoints
  kLanding,    ///< descending to land
};
const char* FlightModeName(FlightMode mode);

struct VehicleState {
  double stamp_s = 0.0;
  FlightMode mode = FlightMode::kDisarmed;
  Eigen::Isometry3d wMd = Eigen::Isometry3d::Identity();  ///< body pose in w
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();          ///< body velocity in w, m/s
  Eigen::Vector3d w_d = Eigen::Vector3d::Zero();          ///< body angular velocity in d, rad/s
  bool link_ok = true;  ///< false when the autopilot has gone silent (the rest is then stale)
};

/// The autopilot's answer to a command (COMMAND_ACK on PX4).
struct CommandAck {
  bool accepted = false;
  std::string reason;  ///< why it was refused; empty when accepted
};

class Autopilot {
 public:
  virtual ~Autopilot() = default;
  virtual VehicleState State() const = 0;
  virtual CommandAck Arm() = 0;
  virtual CommandAck Disarm() = 0;
  /// Climb to `altitude_m` above the take-off point, then hold.
  virtual CommandAck Takeoff(double altitude_m) = 0;
  virtual CommandAck Land() = 0;
  /// Hover where the vehicle is now.
  virtual CommandAck Hold() = 0;
  /// Enter offboard (if not in it) and fly to `p_w` (m, NED) with heading `yaw_rad`.
  /// The stream of setpoints must continue, or the autopilot falls back to hold.
  virtual CommandAck SetPositionTarget(const Eigen::Vector3d& p_w, double yaw_rad) = 0;
};

}  // namespace aerograsp
