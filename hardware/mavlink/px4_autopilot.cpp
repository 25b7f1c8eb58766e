#include "hardware/mavlink/px4_autopilot.h"

#include <chrono>
#include <cmath>
#include <limits>

#include "hardware/rgbd_camera.h"  // HardwareError

namespace aerograsp {
namespace {

using Steady = std::chrono::steady_clock;

double SecondsSince(Steady::time_point t0) {
  return std::chrono::duration<double>(Steady::now() - t0).count();
}

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kThreadPeriod_s = 0.01;

}  // namespace

Px4Autopilot::Px4Autopilot(std::unique_ptr<MavlinkLink> link, const Px4Config& config, Clock clock)
    : config_(config),
      clock_(std::move(clock)),
      link_(std::move(link)),
      encoder_(static_cast<std::uint8_t>(config.system_id),
               static_cast<std::uint8_t>(config.component_id)) {
  if (!config.signing_key_hex.empty()) {
    const auto key = mavlink::ParseKeyHex(config.signing_key_hex);
    if (!key) throw HardwareError("autopilot: signing key is not 64 hex digits");
    encoder_.SetSigning(
        mavlink::SigningKey{*key, static_cast<std::uint8_t>(config.signing_link_id)});
    parser_.RequireSigning(*key);
  }
}

Px4Autopilot::~Px4Autopilot() { StopThread(); }

template <class M>
void Px4Autopilot::Send(const M& message) {
  std::lock_guard<std::mutex> lock(send_mutex_);
  link_->Send(encoder_.Encode(M::kId, mavlink::Pack(message)));
}

void Px4Autopilot::Connect() {
  const auto t0 = Steady::now();
  while (SecondsSince(t0) < config_.connect_timeout_s) {
    SendDue(clock_());
    ReceiveFor(0.05);
    std::lock_guard<std::mutex> lock(mutex_);
    if (heard_) return;
  }
  throw HardwareError("autopilot (" + link_->Describe() + "): no heartbeat from system " +
                      std::to_string(config_.target_system) + " component " +
                      std::to_string(config_.target_component) + " within " +
                      std::to_string(config_.connect_timeout_s).substr(0, 4) + " s");
}

void Px4Autopilot::ReceiveFor(double timeout_s) {
  std::uint8_t buffer[2048];
  std::size_t n = link_->Receive(buffer, sizeof buffer, timeout_s);
  while (n > 0) {
    for (std::size_t i = 0; i < n; ++i) {
      if (parser_.Push(buffer[i]) == mavlink::Parser::Result::kFrame) Handle(parser_.frame());
    }
    n = link_->Receive(buffer, sizeof buffer, 0.0);  // drain what else is waiting
  }
  std::lock_guard<std::mutex> lock(mutex_);
  counters_ = parser_.counters();
}

void Px4Autopilot::Handle(const mavlink::Frame& frame) {
  if (frame.sysid != config_.target_system) return;
  const double now = clock_();
  std::lock_guard<std::mutex> lock(mutex_);
  switch (frame.msgid) {
    case mavlink::Heartbeat::kId: {
      if (frame.compid != config_.target_component)
        return;  // a camera or gimbal of the same system
      const auto hb = mavlink::Unpack<mavlink::Heartbeat>(frame);
      armed_ = hb.base_mode & mavlink::kModeFlagSafetyArmed;
      custom_mode_ = hb.custom_mode;
      last_heartbeat_s_ = now;
      heard_ = true;
      return;
    }
    case mavlink::Attitude::kId: {
      const auto a = mavlink::Unpack<mavlink::Attitude>(frame);
      const Eigen::Matrix3d wRd = (Eigen::AngleAxisd(a.yaw, Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(a.pitch, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(a.roll, Eigen::Vector3d::UnitX()))
                                      .toRotationMatrix();
      telemetry_.wMd.linear() = wRd;
      telemetry_.w_d = Eigen::Vector3d(a.rollspeed, a.pitchspeed, a.yawspeed);
      telemetry_.stamp_s = now;
      return;
    }
    case mavlink::LocalPositionNed::kId: {
      const auto p = mavlink::Unpack<mavlink::LocalPositionNed>(frame);
      telemetry_.wMd.translation() = Eigen::Vector3d(p.x, p.y, p.z);
      telemetry_.v_w = Eigen::Vector3d(p.vx, p.vy, p.vz);
      telemetry_.stamp_s = now;
      return;
    }
    case mavlink::ExtendedSysState::kId:
      landed_state_ = mavlink::Unpack<mavlink::ExtendedSysState>(frame).landed_state;
      return;
    case mavlink::StatusText::kId:
      last_status_text_ = mavlink::Unpack<mavlink::StatusText>(frame).Text();
      return;
    case mavlink::CommandAck::kId: {
      const auto ack = mavlink::Unpack<mavlink::CommandAck>(frame);
      if (ack.target_system != 0 && ack.target_system != config_.system_id)
        return;  // someone else's
      acks_[ack.command] = {ack.result, ++ack_serial_};
      ack_cv_.notify_all();
      return;
    }
    default:
      return;
  }
}

void Px4Autopilot::SendDue(double now_s) {
  bool heartbeat = false, setpoint = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (now_s - last_heartbeat_sent_s_ >= 1.0 / config_.heartbeat_hz) {
      last_heartbeat_sent_s_ = now_s;
      heartbeat = true;
    }
    if (streaming_ && now_s - last_setpoint_sent_s_ >= 1.0 / config_.setpoint_hz - 1e-9) {
      last_setpoint_sent_s_ = now_s;
      setpoint = true;
    }
  }
  if (heartbeat) {
    mavlink::Heartbeat hb;
    hb.type = 18;          // MAV_TYPE_ONBOARD_CONTROLLER
    hb.autopilot = 8;      // MAV_AUTOPILOT_INVALID: not an autopilot
    hb.system_status = 4;  // MAV_STATE_ACTIVE
    Send(hb);
  }
  if (setpoint) SendSetpoint();
}

void Px4Autopilot::SendSetpoint() {
  mavlink::SetPositionTargetLocalNed sp;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    sp.x = static_cast<float>(target_p_w_.x());
    sp.y = static_cast<float>(target_p_w_.y());
    sp.z = static_cast<float>(target_p_w_.z());
    sp.yaw = static_cast<float>(target_yaw_rad_);
  }
  sp.time_boot_ms = static_cast<std::uint32_t>(clock_() * 1000.0);
  sp.type_mask = mavlink::kTypeMaskPositionYaw;
  sp.coordinate_frame = mavlink::kFrameLocalNed;
  sp.target_system = static_cast<std::uint8_t>(config_.target_system);
  sp.target_component = static_cast<std::uint8_t>(config_.target_component);
  Send(sp);
  ++setpoints_sent_;
}

void Px4Autopilot::Spin() {
  ReceiveFor(0.0);
  SendDue(clock_());
}

void Px4Autopilot::StartThread() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    while (running_.load()) {
      ReceiveFor(kThreadPeriod_s);
      SendDue(clock_());
    }
  });
}

void Px4Autopilot::StopThread() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

bool Px4Autopilot::link_ok() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return heard_ && clock_() - last_heartbeat_s_ < config_.link_timeout_s;
}

mavlink::ParserCounters Px4Autopilot::parser_counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

std::int64_t Px4Autopilot::commands_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return commands_sent_;
}

VehicleState Px4Autopilot::State() const {
  const bool ok = link_ok();
  std::lock_guard<std::mutex> lock(mutex_);
  VehicleState state = telemetry_;
  state.link_ok = ok;
  const std::uint8_t main = mavlink::px4::MainMode(custom_mode_),
                     sub = mavlink::px4::SubMode(custom_mode_);
  if (!armed_) {
    state.mode = FlightMode::kDisarmed;
  } else if (landed_state_ == mavlink::kLandedOnGround) {
    state.mode = FlightMode::kLanded;
  } else if (main == mavlink::px4::kMainOffboard) {
    state.mode = FlightMode::kOffboard;
  } else if (main == mavlink::px4::kMainAuto && sub == mavlink::px4::kAutoTakeoff) {
    state.mode = FlightMode::kTakingOff;
  } else if (main == mavlink::px4::kMainAuto && sub == mavlink::px4::kAutoLand) {
    state.mode = FlightMode::kLanding;
  } else {
    state.mode = FlightMode::kHold;
  }
  return state;
}

bool Px4Autopilot::WaitForAck(std::uint16_t command, std::int64_t after_serial, double timeout_s,
                              Ack* ack) {
  const auto t0 = Steady::now();
  auto fresh = [&] {
    const auto it = acks_.find(command);
    if (it == acks_.end() || it->second.serial <= after_serial) return false;
    *ack = it->second;
    return true;
  };
  while (true) {
    const double left = timeout_s - SecondsSince(t0);
    if (running_.load()) {  // the thread receives; wait for it
      std::unique_lock<std::mutex> lock(mutex_);
      if (ack_cv_.wait_for(lock, std::chrono::duration<double>(std::max(0.0, left)), fresh))
        return true;
      if (left <= 0.0) return false;
      continue;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (fresh()) return true;
    }
    if (left <= 0.0) return false;
    ReceiveFor(std::min(left, 0.01));
  }
}

CommandAck Px4Autopilot::Command(std::uint16_t command, const std::array<float, 7>& params,
                                 const char* name) {
  for (int attempt = 0; attempt < config_.command_attempts; ++attempt) {
    std::int64_t serial;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      serial = ack_serial_;
      ++commands_sent_;
      last_status_text_.clear();
    }
    mavlink::CommandLong cmd;
    cmd.param1 = params[0], cmd.param2 = params[1], cmd.param3 = params[2], cmd.param4 = params[3];
    cmd.param5 = params[4], cmd.param6 = params[5], cmd.param7 = params[6];
    cmd.command = command;
    cmd.target_system = static_cast<std::uint8_t>(config_.target_system);
    cmd.target_component = static_cast<std::uint8_t>(config_.target_component);
    cmd.confirmation = static_cast<std::uint8_t>(attempt);
    Send(cmd);
    Ack ack;
    double timeout = config_.command_timeout_s;
    while (WaitForAck(command, serial, timeout, &ack)) {
      if (ack.result == mavlink::kResultInProgress) {  // a final ACK follows
        serial = ack.serial;
        continue;
      }
      if (ack.result == mavlink::kResultAccepted) return {true, ""};
      // PX4 explains refusals in a STATUSTEXT sent with the ACK; give it a moment.
      ReceiveFor(running_.load() ? 0.0 : 0.02);
      std::lock_guard<std::mutex> lock(mutex_);
      std::string reason = std::string(name) + " " + mavlink::MavResultName(ack.result);
      if (!last_status_text_.empty()) reason += ": " + last_status_text_;
      return {false, reason};
    }
  }
  return {false, std::string(name) + ": no COMMAND_ACK after " +
                     std::to_string(config_.command_attempts) + " attempts (" + link_->Describe() +
                     ")"};
}

CommandAck Px4Autopilot::Arm() {
  return Command(mavlink::kCmdComponentArmDisarm, {1, 0, 0, 0, 0, 0, 0}, "arm");
}

CommandAck Px4Autopilot::Disarm() {
  return Command(mavlink::kCmdComponentArmDisarm, {0, 0, 0, 0, 0, 0, 0}, "disarm");
}

CommandAck Px4Autopilot::Takeoff(double altitude_m) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    streaming_ = offboard_accepted_ = offboard_seen_ = false;
  }
  // param4 yaw, param5/6 latitude/longitude NaN: keep the present ones; param7 AMSL altitude.
  return Command(mavlink::kCmdNavTakeoff,
                 {0, 0, 0, kNaN, kNaN, kNaN, static_cast<float>(config_.home_amsl_m + altitude_m)},
                 "take-off");
}

CommandAck Px4Autopilot::Land() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    streaming_ = offboard_accepted_ = offboard_seen_ = false;
  }
  return Command(mavlink::kCmdNavLand, {0, 0, 0, kNaN, kNaN, kNaN, kNaN}, "land");
}

CommandAck Px4Autopilot::Hold() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    streaming_ = offboard_accepted_ = offboard_seen_ = false;
  }
  return Command(mavlink::kCmdDoSetMode,
                 {mavlink::kModeFlagCustomModeEnabled, mavlink::px4::kMainAuto,
                  mavlink::px4::kAutoLoiter, 0, 0, 0, 0},
                 "hold");
}

CommandAck Px4Autopilot::SetPositionTarget(const Eigen::Vector3d& p_w, double yaw_rad) {
  if (!p_w.allFinite() || !std::isfinite(yaw_rad)) return {false, "setpoint refused: not finite"};
  const FlightMode mode = State().mode;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    target_p_w_ = p_w;
    target_yaw_rad_ = yaw_rad;
    streaming_ = true;
    if (offboard_accepted_) {
      if (mode == FlightMode::kOffboard) offboard_seen_ = true;
      // Heartbeats lag the switch: until offboard has been seen, trust the ACK.
      if (!offboard_seen_ || mode == FlightMode::kOffboard) return {true, ""};
      // The autopilot left offboard on its own (failsafe, pilot): do not fight it.
      offboard_accepted_ = offboard_seen_ = false;
      streaming_ = false;
      return {false, std::string("offboard left by the autopilot (now ") + FlightModeName(mode) +
                         "); the next setpoint asks for it again"};
    }
  }
  // PX4 switches to offboard only while setpoints are arriving: stream first.
  const auto t0 = Steady::now();
  const auto period = std::chrono::duration_cast<Steady::duration>(
      std::chrono::duration<double>(1.0 / config_.setpoint_hz));
  auto next = t0;
  while (SecondsSince(t0) < config_.prestream_s) {
    if (Steady::now() >= next) {
      SendSetpoint();
      next += period;
    }
    if (running_.load()) {
      std::this_thread::sleep_until(next);
    } else {
      ReceiveFor(std::max(0.0, std::chrono::duration<double>(next - Steady::now()).count()));
    }
  }
  SendSetpoint();
  const CommandAck ack =
      Command(mavlink::kCmdDoSetMode,
              {mavlink::kModeFlagCustomModeEnabled, mavlink::px4::kMainOffboard, 0, 0, 0, 0, 0},
              "offboard");
  std::lock_guard<std::mutex> lock(mutex_);
  offboard_accepted_ = ack.accepted;
  offboard_seen_ = false;
  if (!ack.accepted) streaming_ = false;
  return ack;
}

}  // namespace aerograsp
