#include "hardware/sim/sim_px4.h"

#include <chrono>
#include <cmath>

#include "hardware/rgbd_camera.h"  // HardwareError

namespace aerograsp {
namespace {

std::uint32_t CustomModeOf(FlightMode mode) {
  using namespace mavlink::px4;
  switch (mode) {
    case FlightMode::kTakingOff:
      return CustomMode(kMainAuto, kAutoTakeoff);
    case FlightMode::kOffboard:
      return CustomMode(kMainOffboard, 0);
    case FlightMode::kLanding:
      return CustomMode(kMainAuto, kAutoLand);
    default:
      return CustomMode(kMainAuto, kAutoLoiter);
  }
}

std::uint8_t LandedStateOf(FlightMode mode) {
  switch (mode) {
    case FlightMode::kDisarmed:
    case FlightMode::kLanded:
      return mavlink::kLandedOnGround;
    case FlightMode::kTakingOff:
      return mavlink::kLandedTakeoff;
    case FlightMode::kLanding:
      return mavlink::kLandedLanding;
    default:
      return mavlink::kLandedInAir;
  }
}

}  // namespace

SimPx4::SimPx4(World* world, const SimPx4Config& config)
    : world_(world),
      config_(config),
      link_("127.0.0.1", 0, "", 0, "simulated PX4"),
      encoder_(static_cast<std::uint8_t>(config.system_id),
               static_cast<std::uint8_t>(config.component_id)) {
  if (!config.signing_key_hex.empty()) {
    const auto key = mavlink::ParseKeyHex(config.signing_key_hex);
    if (!key) throw HardwareError("simulated PX4: signing key is not 64 hex digits");
    encoder_.SetSigning(mavlink::SigningKey{*key, 0});
    parser_.RequireSigning(*key);
  }
  next_fast_s_ = next_slow_s_ = next_heartbeat_s_ = world->now_s();
  thread_ = std::thread([this] { Serve(); });
}

SimPx4::~SimPx4() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

std::int64_t SimPx4::frames_rejected() const { return frames_rejected_; }

template <class M>
void SimPx4::Send(const M& message) {
  if (silent_) return;
  std::lock_guard<std::mutex> lock(send_mutex_);
  link_.Send(encoder_.Encode(M::kId, mavlink::Pack(message)));
}

void SimPx4::Serve() {
  std::uint8_t buffer[2048];
  while (running_.load()) {
    const std::size_t n = link_.Receive(buffer, sizeof buffer, 0.01);
    if (silent_) continue;
    for (std::size_t i = 0; i < n; ++i) {
      const mavlink::Parser::Result r = parser_.Push(buffer[i]);
      if (r == mavlink::Parser::Result::kFrame) {
        Handle(parser_.frame());
      } else if (r != mavlink::Parser::Result::kNeedMore) {
        ++frames_rejected_;
      }
    }
  }
}

void SimPx4::Handle(const mavlink::Frame& frame) {
  if (frame.msgid == mavlink::Heartbeat::kId) {
    // Besides the heartbeats on the simulated clock: answer a companion's at
    // once, so that it can connect before the owner steps the world.
    SendTelemetry(false, true);
  } else if (frame.msgid == mavlink::CommandLong::kId) {
    const auto command = mavlink::Unpack<mavlink::CommandLong>(frame);
    if (command.target_system != config_.system_id) return;
    ++commands_received_;
    if (drop_commands_ > 0) {
      --drop_commands_;
      return;
    }
    HandleCommand(command);
  } else if (frame.msgid == mavlink::SetPositionTargetLocalNed::kId) {
    const auto sp = mavlink::Unpack<mavlink::SetPositionTargetLocalNed>(frame);
    if (sp.target_system != config_.system_id || sp.coordinate_frame != mavlink::kFrameLocalNed)
      return;
    {
      std::lock_guard<std::mutex> lock(world_mutex_);
      last_setpoint_s_ = world_->now_s();
      last_setpoint_ = sp;
      if (world_->vehicle().State().mode == FlightMode::kOffboard) {
        world_->vehicle().SetPositionTarget(world_->now_s(), Eigen::Vector3d(sp.x, sp.y, sp.z),
                                            sp.yaw);
      }
    }
    ++setpoints_received_;  // after the world has it: WaitForSetpoints relies on this order
  }
}

void SimPx4::HandleCommand(const mavlink::CommandLong& command) {
  aerograsp::CommandAck result{false, "unsupported command " + std::to_string(command.command)};
  std::uint8_t refusal = mavlink::kResultTemporarilyRejected;
  {
    std::lock_guard<std::mutex> lock(world_mutex_);
    SimVehicle& vehicle = world_->vehicle();
    const bool refuse = reject_commands_;
    if (refuse) {
      if (first_fault_s_ < 0.0) first_fault_s_ = world_->now_s();
      result = {false, "command refused (simulated fault)"};
    }
    switch (refuse ? -1 : int{command.command}) {
      case -1:
        break;
      case mavlink::kCmdComponentArmDisarm:
        result = command.param1 > 0.5f ? vehicle.Arm() : vehicle.Disarm();
        break;
      case mavlink::kCmdNavTakeoff: {
        const double altitude = std::isnan(command.param7) ? config_.default_takeoff_m
                                                           : command.param7 - config_.home_amsl_m;
        result = vehicle.Takeoff(altitude);
        break;
      }
      case mavlink::kCmdNavLand:
        result = vehicle.Land();
        break;
      case mavlink::kCmdDoSetMode: {
        const int main = static_cast<int>(command.param2), sub = static_cast<int>(command.param3);
        if (main == mavlink::px4::kMainOffboard) {
          if (world_->now_s() - last_setpoint_s_ > config_.offboard_signal_s) {
            result = {false, "Switching to Offboard denied: no offboard signal"};
          } else {
            result = vehicle.SetPositionTarget(
                world_->now_s(),
                Eigen::Vector3d(last_setpoint_.x, last_setpoint_.y, last_setpoint_.z),
                last_setpoint_.yaw);
          }
        } else if (main == mavlink::px4::kMainAuto && sub == mavlink::px4::kAutoLoiter) {
          result = vehicle.Hold();
        } else if (main == mavlink::px4::kMainAuto && sub == mavlink::px4::kAutoLand) {
          result = vehicle.Land();
        } else {
          result = {false,
                    "mode " + std::to_string(main) + "." + std::to_string(sub) + " not simulated"};
          refusal = mavlink::kResultUnsupported;
        }
        break;
      }
      default:
        refusal = mavlink::kResultUnsupported;
        break;
    }
  }
  if (!result.accepted) {
    mavlink::StatusText text;
    text.severity = 4;  // MAV_SEVERITY_WARNING
    text.SetText(result.reason);
    Send(text);
  }
  mavlink::CommandAck ack;
  ack.command = command.command;
  ack.result = result.accepted ? std::uint8_t{mavlink::kResultAccepted} : refusal;
  ack.target_system = 0;  // PX4 leaves it 0 for commands from the companion
  Send(ack);
}

bool SimPx4::WaitForSetpoints(std::int64_t count, double timeout_s) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (setpoints_received_ < count) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  return true;
}

void SimPx4::StepWorld(double dt_s) {
  bool fast = false, slow = false, heartbeat = false;
  {
    std::lock_guard<std::mutex> lock(world_mutex_);
    world_->Step(dt_s);
    const double now = world_->now_s();
    if (now >= config_.faults.faults_from_s) {
      if (config_.faults.silent && !silent_) {
        silent_ = true;
        if (first_fault_s_ < 0.0) first_fault_s_ = now;
      }
      if (config_.faults.reject_commands) reject_commands_ = true;
    }
    if (now >= next_fast_s_ - 1e-9) {
      fast = true;
      next_fast_s_ = now + 1.0 / config_.telemetry_hz;
    }
    if (now >= next_slow_s_ - 1e-9) {
      slow = true;
      next_slow_s_ = now + 1.0 / config_.slow_telemetry_hz;
    }
    if (now >= next_heartbeat_s_ - 1e-9) {
      heartbeat = true;
      next_heartbeat_s_ = now + 1.0 / config_.heartbeat_hz;
    }
  }
  if (fast || slow || heartbeat) SendTelemetry(slow, heartbeat);
}

void SimPx4::SendTelemetry(bool slow, bool heartbeat) {
  VehicleState state;
  double now;
  {
    std::lock_guard<std::mutex> lock(world_mutex_);
    state = world_->vehicle().State();
    now = world_->now_s();
  }
  const auto time_boot_ms = static_cast<std::uint32_t>(now * 1000.0);
  if (heartbeat) {
    mavlink::Heartbeat hb;
    hb.type = 13;       // MAV_TYPE_HEXAROTOR
    hb.autopilot = 12;  // MAV_AUTOPILOT_PX4
    const bool armed = state.mode != FlightMode::kDisarmed;
    hb.base_mode =
        mavlink::kModeFlagCustomModeEnabled | (armed ? mavlink::kModeFlagSafetyArmed : 0);
    hb.custom_mode = CustomModeOf(state.mode);
    hb.system_status = armed ? 4 : 3;  // MAV_STATE_ACTIVE : MAV_STATE_STANDBY
    Send(hb);
  }
  const Eigen::Matrix3d R = state.wMd.linear();
  mavlink::Attitude att;
  att.time_boot_ms = time_boot_ms;
  att.roll = static_cast<float>(std::atan2(R(2, 1), R(2, 2)));
  att.pitch = static_cast<float>(-std::asin(std::clamp(R(2, 0), -1.0, 1.0)));
  att.yaw = static_cast<float>(std::atan2(R(1, 0), R(0, 0)));
  att.rollspeed = static_cast<float>(state.w_d.x());
  att.pitchspeed = static_cast<float>(state.w_d.y());
  att.yawspeed = static_cast<float>(state.w_d.z());
  Send(att);
  mavlink::LocalPositionNed pos;
  pos.time_boot_ms = time_boot_ms;
  pos.x = static_cast<float>(state.wMd.translation().x());
  pos.y = static_cast<float>(state.wMd.translation().y());
  pos.z = static_cast<float>(state.wMd.translation().z());
  pos.vx = static_cast<float>(state.v_w.x());
  pos.vy = static_cast<float>(state.v_w.y());
  pos.vz = static_cast<float>(state.v_w.z());
  Send(pos);
  if (slow) {
    mavlink::ExtendedSysState ext;
    ext.vtol_state = 0;
    ext.landed_state = LandedStateOf(state.mode);
    Send(ext);
    mavlink::SysStatus status;
    status.voltage_battery = 16800;  // mV, 4S full
    status.battery_remaining = 90;
    Send(status);
  }
}

}  // namespace aerograsp
