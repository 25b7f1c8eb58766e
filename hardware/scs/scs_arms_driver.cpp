#include "hardware/scs/scs_arms_driver.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include "hardware/rgbd_camera.h"  // HardwareError

namespace aerograsp {
namespace {

constexpr double kSimServoRange_rad = 220.0 * M_PI / 180.0;  // hardware/sim/world_config.h default
constexpr int kGripperStillCounts = 3;                       // smaller changes are noise
constexpr double kGripperSettle_s = 0.15;                    // no change for this long: stopped
constexpr int kGripperAtGoalCounts = 12;                     // within this of the goal: arrived

int SignedLoad(int raw) { return (raw & 0x400) ? -(raw & 0x3FF) : (raw & 0x3FF); }

}  // namespace

ScsArmsConfig ScsArmsConfig::Default(const Platform& platform) {
  ScsArmsConfig config;
  for (Side side : kSides) {
    const int k = static_cast<int>(side) + 1;
    const ArmModel& arm = platform.arm(side);
    auto& joints = config.joints[static_cast<int>(side)];
    for (int i = 0; i < arm.dof(); ++i) {
      const double lower = arm.lower_limits()[i];
      joints.push_back({10 * k + i + 1, lower, lower + kSimServoRange_rad});
    }
    config.grippers[static_cast<int>(side)].id = 10 * k + 7;
  }
  return config;
}

ScsArmsDriver::ScsArmsDriver(const Platform& platform, const ScsArmsConfig& config, Clock clock)
    : config_(config),
      clock_(std::move(clock)),
      max_aperture_m_(platform.config().gripper.max_aperture_m) {
  for (Side side : kSides) {
    const int s = static_cast<int>(side);
    const ArmModel& arm = platform.arm(side);
    if (static_cast<int>(config.joints[s].size()) != arm.dof()) {
      throw HardwareError("servo bus " + config.port + ": " + SideName(side) + " arm has " +
                          std::to_string(arm.dof()) + " joints but " +
                          std::to_string(config.joints[s].size()) + " servos are configured");
    }
    arms_[s].lower = arm.lower_limits();
    arms_[s].upper = arm.upper_limits();
    arms_[s].measured = arms_[s].command = arms_[s].target = Eigen::VectorXd::Zero(arm.dof());
    for (int i = 0; i < arm.dof(); ++i) {
      servos_.push_back(
          {config.joints[s][i].id, std::string(SideName(side)) + " j" + std::to_string(i + 1)});
    }
    servos_.push_back({config.grippers[s].id, std::string(SideName(side)) + " gripper"});
  }
  bus_ =
      std::make_unique<ScsBus>(std::make_unique<SerialPort>(config.port, config.baud, "servo bus"),
                               config.reply_timeout_s, config.local_echo);
  // Every servo must answer before anything moves.
  std::vector<std::string> missing;
  for (ScsServoStatus& servo : servos_) {
    std::vector<std::uint8_t> data;
    BusStatus status = BusStatus::kTimeout;
    for (int attempt = 0; attempt < 3 && status != BusStatus::kOk; ++attempt) {
      status = bus_->Read(static_cast<std::uint8_t>(servo.id), scs::reg::kPresentPosition, 2, &data,
                          &servo.error);
    }
    if (status != BusStatus::kOk) {
      missing.push_back(std::to_string(servo.id) + " (" + servo.name + ", " +
                        BusStatusName(status) + ")");
      continue;
    }
    servo.raw_position = scs::GetU16(data.data());
  }
  if (!missing.empty()) {
    std::ostringstream msg;
    msg << "servo bus " << config.port << ": no reply from servo";
    if (missing.size() > 1) msg << "s";
    for (std::size_t i = 0; i < missing.size(); ++i) msg << (i ? ", " : " ") << missing[i];
    throw HardwareError(msg.str());
  }
  const double now = clock_();
  for (Side side : kSides) {
    const int s = static_cast<int>(side);
    for (int i = 0; i < arms_[s].measured.size(); ++i) {
      arms_[s].measured[i] =
          config_.joints[s][i].AngleFromRaw(servos_[ServoIndex(side, i)].raw_position);
    }
    arms_[s].command = arms_[s].target = arms_[s].measured;
    UpdateGripperState(
        side, servos_[ServoIndex(side, static_cast<int>(config_.joints[s].size()))].raw_position,
        now);
  }
  if (config_.torque_on_start) SetTorque(true);
}

ScsArmsDriver::~ScsArmsDriver() { StopThread(); }

std::size_t ScsArmsDriver::ServoIndex(Side side, int joint) const {
  // joint == dof is the gripper.
  return side == Side::kLeft ? static_cast<std::size_t>(joint)
                             : config_.joints[0].size() + 1 + static_cast<std::size_t>(joint);
}

void ScsArmsDriver::SetJointTargets(Side side, const Eigen::VectorXd& q_rad) {
  std::lock_guard<std::mutex> lock(mutex_);
  ArmState& arm = arms_[static_cast<int>(side)];
  if (q_rad.size() != arm.target.size() || !q_rad.allFinite())
    return;  // not a command: keep the last
  arm.target = q_rad.cwiseMax(arm.lower).cwiseMin(arm.upper);
  arm.target_stamp_s = clock_();
  arm.has_target = true;
}

Eigen::VectorXd ScsArmsDriver::JointPositions(Side side) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arms_[static_cast<int>(side)].measured;
}

void ScsArmsDriver::SetGripper(Side side, GripperCommand command) {
  std::lock_guard<std::mutex> lock(mutex_);
  arms_[static_cast<int>(side)].gripper = command;
}

GripperState ScsArmsDriver::Gripper(Side side) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arms_[static_cast<int>(side)].gripper_state;
}

void ScsArmsDriver::Stop() {
  std::lock_guard<std::mutex> lock(mutex_);
  const double now = clock_();
  for (ArmState& arm : arms_) {
    arm.target = arm.measured;
    arm.target_stamp_s = now;
    arm.has_target = true;
  }
}

Eigen::VectorXd ScsArmsDriver::last_command(Side side) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arms_[static_cast<int>(side)].command;
}

std::vector<ScsServoStatus> ScsArmsDriver::servo_statuses() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return servos_;
}

BusCounters ScsArmsDriver::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

BusStatus ScsArmsDriver::SetTorque(bool on) {
  std::vector<scs::SyncEntry> entries;
  for (const ScsServoStatus& servo : servos_) {
    entries.push_back(
        {static_cast<std::uint8_t>(servo.id), {static_cast<std::uint8_t>(on ? 1 : 0)}});
  }
  return bus_->SyncWrite(scs::reg::kTorqueEnable, 1, entries);
}

BusStatus ScsArmsDriver::SetTorque(Side side, bool on) {
  std::vector<scs::SyncEntry> entries;
  for (const ServoCalibration& joint : config_.joints[static_cast<int>(side)]) {
    entries.push_back(
        {static_cast<std::uint8_t>(joint.id), {static_cast<std::uint8_t>(on ? 1 : 0)}});
  }
  return bus_->SyncWrite(scs::reg::kTorqueEnable, 1, entries);
}

void ScsArmsDriver::UpdateGripperState(Side side, int raw, double now_s) {
  ArmState& arm = arms_[static_cast<int>(side)];
  const GripperServoConfig& g = config_.grippers[static_cast<int>(side)];
  if (raw < 0) return;
  const double t = double(raw - g.raw_closed) / double(g.raw_open - g.raw_closed);
  GripperState& state = arm.gripper_state;
  state.aperture_m = std::clamp(t, 0.0, 1.0) * max_aperture_m_;
  if (arm.gripper_last_raw < 0 || std::abs(raw - arm.gripper_last_raw) > kGripperStillCounts) {
    arm.gripper_changed_s = now_s;
    arm.gripper_last_raw = raw;
  }
  const int goal = arm.gripper == GripperCommand::kOpen ? g.raw_open : g.raw_closed;
  const bool at_goal = std::abs(raw - goal) <= kGripperAtGoalCounts;
  state.moving = !at_goal && now_s - arm.gripper_changed_s < kGripperSettle_s;
  const bool closing = arm.gripper == GripperCommand::kClose;
  state.closed = closing && !state.moving;
  state.holding =
      state.closed && !at_goal;  // stopped before closing fully: something is between the fingers
}

CycleReport ScsArmsDriver::Cycle() {
  CycleReport report;
  const double now = clock_();
  std::vector<scs::SyncEntry> entries;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (Side side : kSides) {
      const int s = static_cast<int>(side);
      ArmState& arm = arms_[s];
      const bool stale = !arm.has_target || now - arm.target_stamp_s > config_.stale_after_s;
      if (arm.has_target && stale) report.stale = true;
      if (!stale) {
        const Eigen::VectorXd step = (arm.target - arm.command)
                                         .cwiseMax(-config_.max_step_rad)
                                         .cwiseMin(config_.max_step_rad);
        arm.command += step;
      }
      for (int i = 0; i < arm.command.size(); ++i) {
        std::vector<std::uint8_t> data(6);
        scs::PutU16(static_cast<std::uint16_t>(config_.joints[s][i].RawFromAngle(arm.command[i])),
                    &data[0]);
        scs::PutU16(static_cast<std::uint16_t>(config_.goal_time_ms), &data[2]);
        scs::PutU16(static_cast<std::uint16_t>(config_.goal_speed), &data[4]);
        entries.push_back({static_cast<std::uint8_t>(config_.joints[s][i].id), std::move(data)});
      }
      const GripperServoConfig& g = config_.grippers[s];
      std::vector<std::uint8_t> data(6);
      scs::PutU16(static_cast<std::uint16_t>(arm.gripper == GripperCommand::kOpen ? g.raw_open
                                                                                  : g.raw_closed),
                  &data[0]);
      scs::PutU16(static_cast<std::uint16_t>(config_.goal_time_ms), &data[2]);
      scs::PutU16(static_cast<std::uint16_t>(config_.goal_speed), &data[4]);
      entries.push_back({static_cast<std::uint8_t>(g.id), std::move(data)});
    }
  }
  const std::int64_t late_before = bus_->counters().late_replies;
  report.sync_write = bus_->SyncWrite(scs::reg::kGoalPosition, 6, entries);

  // Positions of every servo, then one servo's status.
  std::vector<int> raw(servos_.size(), -1);
  std::vector<std::uint8_t> errors(servos_.size(), 0);
  for (std::size_t k = 0; k < servos_.size(); ++k) {
    std::vector<std::uint8_t> data;
    if (bus_->Read(static_cast<std::uint8_t>(servos_[k].id), scs::reg::kPresentPosition, 2, &data,
                   &errors[k]) == BusStatus::kOk) {
      raw[k] = scs::GetU16(data.data());
    } else {
      ++report.failed_reads;
    }
  }
  const std::size_t status_index = next_status_;
  next_status_ = (next_status_ + 1) % servos_.size();
  std::vector<std::uint8_t> status_data;
  const bool status_ok = bus_->Read(static_cast<std::uint8_t>(servos_[status_index].id),
                                    scs::reg::kPresentLoad, 4, &status_data) == BusStatus::kOk;
  report.late_replies = static_cast<int>(bus_->counters().late_replies - late_before);

  std::lock_guard<std::mutex> lock(mutex_);
  counters_ = bus_->counters();
  for (std::size_t k = 0; k < servos_.size(); ++k) {
    if (raw[k] < 0) {
      ++servos_[k].failed_reads;
      continue;
    }
    servos_[k].raw_position = raw[k];
    servos_[k].error = errors[k];
    servos_[k].failed_reads = 0;
    ++servos_[k].good_reads;
  }
  if (status_ok) {
    ScsServoStatus& servo = servos_[status_index];
    servo.load = SignedLoad(scs::GetU16(status_data.data()));
    servo.voltage_v = 0.1 * status_data[2];
    servo.temperature_c = status_data[3];
  }
  for (Side side : kSides) {
    const int s = static_cast<int>(side);
    ArmState& arm = arms_[s];
    for (int i = 0; i < arm.measured.size(); ++i) {
      const int r = raw[ServoIndex(side, i)];
      if (r >= 0) arm.measured[i] = config_.joints[s][i].AngleFromRaw(r);
    }
    UpdateGripperState(side, raw[ServoIndex(side, static_cast<int>(arm.measured.size()))], now);
  }
  return report;
}

void ScsArmsDriver::StartThread() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / config_.rate_hz));
    auto next = std::chrono::steady_clock::now();
    while (running_.load()) {
      Cycle();
      next += period;
      const auto now = std::chrono::steady_clock::now();
      if (next < now) next = now;  // overran: do not try to catch up
      std::this_thread::sleep_until(next);
    }
  });
}

void ScsArmsDriver::StopThread() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

}  // namespace aerograsp
