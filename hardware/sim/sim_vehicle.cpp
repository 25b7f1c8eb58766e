#include "hardware/sim/sim_vehicle.h"

#include <cmath>

namespace aerograsp {
namespace {

constexpr double kTakeoffTolerance_m = 0.05;  // take-off done within this of the altitude
constexpr double kLandingSpeed_mps = 0.5;
constexpr double kGustFrequency_hz = 0.5;  // the position loop's disturbance rejection
constexpr double kGustDamping = 0.7;
constexpr double kSwayFadeIn_s = 2.0;

Eigen::Matrix3d RotationFrd(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

CommandAck Refuse(const std::string& reason) { return {false, reason}; }
CommandAck Accept() { return {true, ""}; }

}  // namespace

SimVehicle::SimVehicle(const VehicleSimConfig& config, std::uint64_t seed)
    : config_(config), rng_(seed) {
  for (int i = 0; i < 3; ++i) {
    sway_phase_[i] = rng_.Uniform(0.0, 2.0 * M_PI);
    tilt_phase_[i] = rng_.Uniform(0.0, 2.0 * M_PI);
  }
  yaw_nominal_rad_ = hold_yaw_rad_ = config.start_yaw_rad;
  if (config.start == "hover") {
    p_nominal_w_ = hold_w_ = config.start_w_m;
    state_.mode = FlightMode::kHold;
    airborne_since_s_ = -kSwayFadeIn_s;  // in the air for a while already
  } else {
    p_nominal_w_ = hold_w_ = Eigen::Vector3d(0.0, 0.0, -config.landed_height_m);
    state_.mode = FlightMode::kDisarmed;
  }
  UpdatePose(0.0, 0.0);
}

bool SimVehicle::Flying() const {
  return state_.mode != FlightMode::kDisarmed && state_.mode != FlightMode::kLanded;
}

CommandAck SimVehicle::Arm() {
  if (state_.mode != FlightMode::kDisarmed) return Accept();  // already armed
  state_.mode = FlightMode::kLanded;
  return Accept();
}

CommandAck SimVehicle::Disarm() {
  if (Flying()) return Refuse("disarm refused: the vehicle is flying (land first)");
  state_.mode = FlightMode::kDisarmed;
  return Accept();
}

CommandAck SimVehicle::Takeoff(double altitude_m) {
  if (state_.mode == FlightMode::kDisarmed) return Refuse("take-off refused: not armed");
  if (!(altitude_m > config_.landed_height_m && altitude_m < 100.0)) {
    return Refuse("take-off refused: altitude " + std::to_string(altitude_m) + " m out of range");
  }
  if (Flying()) return Refuse("take-off refused: already flying");
  hold_w_ = Eigen::Vector3d(p_nominal_w_.x(), p_nominal_w_.y(), -altitude_m);
  hold_yaw_rad_ = yaw_nominal_rad_;
  state_.mode = FlightMode::kTakingOff;
  return Accept();
}

CommandAck SimVehicle::Land() {
  if (!Flying()) return Refuse("land refused: not flying");
  hold_w_ = Eigen::Vector3d(p_nominal_w_.x(), p_nominal_w_.y(), -config_.landed_height_m);
  state_.mode = FlightMode::kLanding;
  return Accept();
}

CommandAck SimVehicle::Hold() {
  if (!Flying()) return Refuse("hold refused: not flying");
  hold_w_ = p_nominal_w_;
  hold_yaw_rad_ = yaw_nominal_rad_;
  state_.mode = FlightMode::kHold;
  setpoints_.clear();
  return Accept();
}

CommandAck SimVehicle::SetPositionTarget(double t_s, const Eigen::Vector3d& p_w, double yaw_rad) {
  if (!p_w.allFinite() || !std::isfinite(yaw_rad)) return Refuse("setpoint refused: not finite");
  if (!Flying() || state_.mode == FlightMode::kLanding || state_.mode == FlightMode::kTakingOff) {
    return Refuse(std::string("setpoint refused in mode ") + FlightModeName(state_.mode));
  }
  if (state_.mode != FlightMode::kOffboard) {
    active_ = {t_s, p_nominal_w_, yaw_nominal_rad_};  // until the first setpoint takes effect
    state_.mode = FlightMode::kOffboard;
  }
  setpoints_.push_back({t_s, p_w, yaw_rad});
  last_setpoint_s_ = t_s;
  return Accept();
}

void SimVehicle::Step(double t_s, double dt_s) {
  const double now = t_s + dt_s;
  Eigen::Vector3d target = hold_w_;
  double target_yaw = hold_yaw_rad_;
  double max_speed = config_.max_speed_mps;
  switch (state_.mode) {
    case FlightMode::kDisarmed:
    case FlightMode::kLanded:
      target = p_nominal_w_;
      break;
    case FlightMode::kTakingOff:
      if (std::abs(p_nominal_w_.z() - hold_w_.z()) < kTakeoffTolerance_m)
        state_.mode = FlightMode::kHold;
      break;
    case FlightMode::kLanding:
      max_speed = std::min(max_speed, kLandingSpeed_mps);
      if (p_nominal_w_.z() > -config_.landed_height_m - 0.01) {
        p_nominal_w_.z() = -config_.landed_height_m;
        state_.mode = FlightMode::kLanded;
      }
      break;
    case FlightMode::kHold:
      break;
    case FlightMode::kOffboard:
      while (!setpoints_.empty() && setpoints_.front().stamp_s + config_.delay_s <= now) {
        active_ = setpoints_.front();
        setpoints_.pop_front();
      }
      if (now - last_setpoint_s_ > config_.offboard_timeout_s) {  // PX4 offboard loss failsafe
        Hold();
        break;
      }
      target = active_.p_w;
      target_yaw = active_.yaw_rad;
      break;
  }
  if (Flying()) {
    Eigen::Vector3d v = (target - p_nominal_w_) / config_.response_time_s;
    if (v.norm() > max_speed) v *= max_speed / v.norm();
    v_nominal_w_ = v;
    p_nominal_w_ += v * dt_s;
    const double yaw_error = std::remainder(target_yaw - yaw_nominal_rad_, 2.0 * M_PI);
    yaw_nominal_rad_ += yaw_error * std::min(1.0, dt_s / config_.response_time_s);
  } else {
    v_nominal_w_.setZero();
  }
  UpdatePose(now, dt_s);
}

void SimVehicle::UpdatePose(double t_s, double dt_s) {
  Eigen::Vector3d sway = Eigen::Vector3d::Zero();
  double roll = 0.0, pitch = 0.0;
  if (Flying()) {
    // Sway fades in over the first seconds in the air (no jump at take-off).
    if (std::isnan(airborne_since_s_)) airborne_since_s_ = t_s;
    const double fade = std::min(1.0, (t_s - airborne_since_s_) / kSwayFadeIn_s);
    for (int i = 0; i < 3; ++i) {
      const double w = 2.0 * M_PI * config_.sway_frequency_hz[i];
      sway[i] = fade * config_.sway_amplitude_m[i] * std::sin(w * t_s + sway_phase_[i]);
    }
    roll = fade * config_.tilt_amplitude_rad *
           std::sin(2.0 * M_PI * config_.sway_frequency_hz.y() * t_s + tilt_phase_.x());
    pitch = fade * config_.tilt_amplitude_rad *
            std::sin(2.0 * M_PI * config_.sway_frequency_hz.x() * t_s + tilt_phase_.y());
  } else {
    airborne_since_s_ = std::nan("");
  }
  if (Flying() && dt_s > 0.0) {
    // Gusts: velocity kicks into a damped second-order disturbance.
    if (rng_.Uniform() < config_.gust_rate_hz * dt_s) {
      const double heading = rng_.Uniform(0.0, 2.0 * M_PI);
      gust_rate_w_ += config_.gust_speed_mps *
                      Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.3 * rng_.Normal());
    }
    const double wn = 2.0 * M_PI * kGustFrequency_hz;
    gust_rate_w_ += (-wn * wn * gust_w_ - 2.0 * kGustDamping * wn * gust_rate_w_) * dt_s;
    gust_w_ += gust_rate_w_ * dt_s;
    // Drift: Ornstein-Uhlenbeck with the configured stationary spread.
    const double tau = config_.drift_time_constant_s;
    const Eigen::Vector3d noise(rng_.Normal(), rng_.Normal(), rng_.Normal());
    drift_w_ +=
        -drift_w_ * (dt_s / tau) + config_.drift_std_m * std::sqrt(2.0 * dt_s / tau) * noise;
  } else if (!Flying()) {
    gust_w_.setZero();
    gust_rate_w_.setZero();
    drift_w_.setZero();
  }
  const Eigen::Vector3d p_w = p_nominal_w_ + sway + gust_w_ + drift_w_;
  if (dt_s > 0.0) {
    state_.v_w = (p_w - state_.wMd.translation()) / dt_s;
    // Small tilts: body rates are the roll and pitch rates (yaw rate neglected).
    state_.w_d =
        Eigen::Vector3d((roll - last_roll_rad_) / dt_s, (pitch - last_pitch_rad_) / dt_s, 0.0);
  }
  last_roll_rad_ = roll;
  last_pitch_rad_ = pitch;
  state_.wMd.linear() = RotationFrd(roll, pitch, yaw_nominal_rad_);
  state_.wMd.translation() = p_w;
  state_.stamp_s = t_s;
}

}  // namespace aerograsp
