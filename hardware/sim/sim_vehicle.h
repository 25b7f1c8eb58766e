// The simulated multirotor and its autopilot: PX4-like flight modes, a
// first-order response to position setpoints after a delay, and the hover
// disturbances (sway, tilt, gusts, slow drift). World frame w is NED.
#pragma once

#include <cmath>
#include <deque>

#include "core/random.h"
#include "hardware/autopilot.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {

class SimVehicle {
 public:
  SimVehicle(const VehicleSimConfig& config, std::uint64_t seed);

  /// Advances from time `t_s` by `dt_s` (the world calls this with its physics step).
  void Step(double t_s, double dt_s);
  VehicleState State() const { return state_; }

  // The autopilot's commands, accepted or refused as PX4 would.
  CommandAck Arm();
  CommandAck Disarm();
  CommandAck Takeoff(double altitude_m);
  CommandAck Land();
  CommandAck Hold();
  CommandAck SetPositionTarget(double t_s, const Eigen::Vector3d& p_w, double yaw_rad);

 private:
  bool Flying() const;
  void UpdatePose(double t_s, double dt_s);

  VehicleSimConfig config_;
  FastRandom rng_;
  VehicleState state_;
  // What the position controller tracks, before disturbances.
  Eigen::Vector3d p_nominal_w_;
  Eigen::Vector3d v_nominal_w_ = Eigen::Vector3d::Zero();
  double yaw_nominal_rad_;
  Eigen::Vector3d hold_w_;  // target in hold / take-off / landing
  double hold_yaw_rad_;
  struct Setpoint {
    double stamp_s;
    Eigen::Vector3d p_w;
    double yaw_rad;
  };
  std::deque<Setpoint> setpoints_;  // received, not yet effective (delay)
  Setpoint active_{0.0, Eigen::Vector3d::Zero(), 0.0};
  double last_setpoint_s_ = -1e9;
  // Disturbances.
  Eigen::Vector3d sway_phase_, tilt_phase_;
  Eigen::Vector3d gust_w_ = Eigen::Vector3d::Zero(), gust_rate_w_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d drift_w_ = Eigen::Vector3d::Zero();
  double last_roll_rad_ = 0.0, last_pitch_rad_ = 0.0;
  double airborne_since_s_ = std::nan("");  // start of the present flight; NaN on the ground
};

}  // namespace aerograsp
