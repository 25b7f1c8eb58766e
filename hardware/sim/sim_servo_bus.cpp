#include "hardware/sim/sim_servo_bus.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>

namespace aerograsp {
namespace {

bool Contains(const std::vector<int>& ids, int id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

constexpr int kHoldingLoad = 600;  // PRESENT_LOAD of a gripper squeezing an object
constexpr int kIdleLoad = 40;
constexpr int kVoltage_dv = 74;  // PRESENT_VOLTAGE of a healthy servo: 7.4 V
constexpr int kTemperature_c = 35;

/// The driver takes `bytes` as the reply it waits for: a well-formed status
/// packet that answers its exchange (scs::AnswersExchange; another one is a
/// late reply of an earlier request, which it skips).
bool AnswersRequest(const std::vector<std::uint8_t>& bytes, int id, std::size_t params) {
  scs::PacketParser parser;
  for (std::uint8_t b : bytes) {
    if (parser.Push(b) == scs::PacketParser::Result::kPacket)
      return scs::AnswersExchange(parser.packet(), static_cast<std::uint8_t>(id), params);
  }
  return false;
}

/// The parameter bytes of the reply the driver waits for after `request`: a
/// READ's length, none for the others.
std::size_t ReplyParams(const scs::Packet& request) {
  return request.code == scs::kRead && request.params.size() == 2 ? request.params[1] : 0;
}

}  // namespace

SimServoBus::SimServoBus(World* world, const ScsArmsConfig& servos, const SimServoBusConfig& config)
    : world_(world),
      servos_config_(servos),
      config_(config),
      rng_(config.seed),
      driver_s_(world->now_s()),
      wire_free_s_(world->now_s()) {
  for (Side side : {Side::kLeft, Side::kRight}) {
    const int s = static_cast<int>(side);
    for (std::size_t i = 0; i < servos.joints[s].size(); ++i) {
      servos_.push_back(
          {servos.joints[s][i].id, side, static_cast<int>(i), servos.joints[s][i], {}});
    }
    const GripperServoConfig& g = servos.grippers[s];
    // The gripper's "calibration" maps raw to the fraction open (0 closed, 1 open).
    const double at_min = -double(g.raw_closed) / (g.raw_open - g.raw_closed);
    servos_.push_back({g.id,
                       side,
                       -1,
                       {g.id, at_min, at_min + double(kScsMaxRaw) / (g.raw_open - g.raw_closed)},
                       {}});
  }
  for (Servo& servo : servos_) {
    servo.regs.assign(scs::reg::kCount, 0);
    servo.regs[scs::reg::kId] = static_cast<std::uint8_t>(servo.id);
    servo.regs[scs::reg::kBaudRate] = 0;  // 1 Mbaud
    scs::PutU16(0, &servo.regs[scs::reg::kMinAngle]);
    scs::PutU16(kScsMaxRaw, &servo.regs[scs::reg::kMaxAngle]);
    scs::PutU16(1000, &servo.regs[scs::reg::kMaxTorque]);
    servo.regs[scs::reg::kVoltage] = kVoltage_dv;
    servo.regs[scs::reg::kTemperature] = kTemperature_c;
  }
  SyncWithWorld();
  // Goals start where the servos are (a powered servo holds its position).
  for (Servo& servo : servos_) {
    servo.regs[scs::reg::kGoalPosition] = servo.regs[scs::reg::kPresentPosition];
    servo.regs[scs::reg::kGoalPosition + 1] = servo.regs[scs::reg::kPresentPosition + 1];
  }
  thread_ = std::thread([this] { Serve(); });
}

SimServoBus::~SimServoBus() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void SimServoBus::SetFaults(const SimServoBusConfig& config) {
  std::lock_guard<std::mutex> lock(mutex_);
  config_ = config;
}

double SimServoBus::faults_on_since_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return faults_on_since_s_;
}

SimServoBusCounters SimServoBus::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

std::vector<std::uint8_t> SimServoBus::Registers(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Servo& servo : servos_) {
    if (servo.id == id) return servo.regs;
  }
  return {};
}

SimServoBus::Servo* SimServoBus::Find(int id) {
  for (Servo& servo : servos_) {
    if (servo.id == id) return &servo;
  }
  return nullptr;
}

void SimServoBus::SyncWithWorld() {
  std::lock_guard<std::mutex> lock(mutex_);
  driver_s_ = std::max(driver_s_, world_->now_s());  // the driver's next cycle
  faults_on_ = world_->now_s() >= config_.faults_from_s;
  const bool any_fault = !config_.silent_ids.empty() || !config_.slow_ids.empty() ||
                         !config_.hot_ids.empty() || !config_.low_voltage_ids.empty() ||
                         !config_.offset_ids.empty() || config_.corrupt_probability > 0.0;
  if (faults_on_ && any_fault && faults_on_since_s_ < 0.0) faults_on_since_s_ = world_->now_s();
  for (Servo& servo : servos_) {
    const bool hot = faults_on_ && Contains(config_.hot_ids, servo.id);
    const bool low = faults_on_ && Contains(config_.low_voltage_ids, servo.id);
    servo.regs[scs::reg::kTemperature] =
        static_cast<std::uint8_t>(hot ? config_.hot_temperature_c : kTemperature_c);
    servo.regs[scs::reg::kVoltage] =
        static_cast<std::uint8_t>(low ? std::lround(10.0 * config_.low_voltage_v) : kVoltage_dv);
  }
  for (Side side : {Side::kLeft, Side::kRight}) {
    SimArm& arm = world_->arm(side);
    Eigen::VectorXd target = arm.target_rad();
    bool any_torque = false;
    for (Servo& servo : servos_) {
      if (servo.side != side) continue;
      const bool torque = servo.regs[scs::reg::kTorqueEnable] != 0;
      const int goal = scs::GetU16(&servo.regs[scs::reg::kGoalPosition]);
      if (servo.joint < 0) {
        if (torque) {
          const bool close = servo.calibration.AngleFromRaw(goal) < 0.5;
          world_->SetGripper(side, close ? GripperCommand::kClose : GripperCommand::kOpen);
        }
        const GripperState g = world_->gripper(side);
        const double open_fraction =
            g.aperture_m / world_->platform().config().gripper.max_aperture_m;
        scs::PutU16(static_cast<std::uint16_t>(servo.calibration.RawFromAngle(open_fraction)),
                    &servo.regs[scs::reg::kPresentPosition]);
        scs::PutU16(g.holding ? kHoldingLoad : kIdleLoad, &servo.regs[scs::reg::kPresentLoad]);
        servo.regs[scs::reg::kMoving] = g.moving ? 1 : 0;
        continue;
      }
      const int i = servo.joint;
      // A servo whose position sensor is off: it reads offset_rad more than
      // where it is and, as its own control loop uses the same sensor, goes to
      // offset_rad less than its goal. So holding its reading holds it where it is.
      const double offset_rad = faults_on_ && Contains(config_.offset_ids, servo.id)
                                    ? config_.offset_deg * M_PI / 180.0
                                    : 0.0;
      // A limp servo (torque off) stays where it is.
      target[i] = torque ? servo.calibration.AngleFromRaw(goal) - offset_rad : arm.q_true_rad()[i];
      any_torque = any_torque || torque;
      const int present = servo.calibration.RawFromAngle(arm.q_true_rad()[i] + offset_rad);
      scs::PutU16(static_cast<std::uint16_t>(present), &servo.regs[scs::reg::kPresentPosition]);
      scs::PutU16(kIdleLoad, &servo.regs[scs::reg::kPresentLoad]);
      servo.regs[scs::reg::kMoving] = std::abs(present - goal) > 1 && torque ? 1 : 0;
    }
    (void)any_torque;
    arm.SetTarget(target);
  }
}

void SimServoBus::Serve() {
  scs::PacketParser parser;
  std::uint8_t buffer[512];
  std::size_t packet_bytes = 0;  // bytes of the packet being parsed, for the wire timing
  while (running_.load()) {
    pollfd p{pty_.master_fd(), POLLIN, 0};
    if (::poll(&p, 1, 5) <= 0 || !(p.revents & POLLIN)) continue;
    const ssize_t n = ::read(pty_.master_fd(), buffer, sizeof buffer);
    if (n <= 0) {
      if (n < 0 && errno != EAGAIN && errno != EINTR && errno != EIO) break;
      continue;
    }
    for (ssize_t i = 0; i < n; ++i) {
      ++packet_bytes;
      const scs::PacketParser::Result r = parser.Push(buffer[i]);
      if (r == scs::PacketParser::Result::kNeedMore) continue;
      if (r == scs::PacketParser::Result::kPacket) {
        Handle(parser.packet(), packet_bytes);
      } else {
        std::lock_guard<std::mutex> lock(mutex_);
        ++counters_.bad_packets;
      }
      packet_bytes = 0;
    }
  }
}

void SimServoBus::Handle(const scs::Packet& packet, std::size_t wire_bytes) {
  std::unique_lock<std::mutex> lock(mutex_);
  ++counters_.packets;
  // Replies that came while the driver was not listening: it discards them
  // before it sends. Then the request occupies the wire for its bytes.
  pending_.erase(std::remove_if(pending_.begin(), pending_.end(),
                                [this](const Pending& p) { return p.due_s <= driver_s_; }),
                 pending_.end());
  wire_free_s_ = std::max(wire_free_s_, driver_s_) + config_.byte_time_s * wire_bytes;
  if (packet.id == scs::kBroadcastId) {
    if (packet.code == scs::kSyncWrite && packet.params.size() >= 2) {
      const std::size_t address = packet.params[0], length = packet.params[1];
      for (std::size_t k = 2; k + 1 + length <= packet.params.size(); k += 1 + length) {
        Servo* servo = Find(packet.params[k]);
        if (!servo || (faults_on_ && Contains(config_.silent_ids, servo->id)) ||
            address + length > scs::reg::kCount)
          continue;
        std::copy_n(packet.params.begin() + k + 1, length, servo->regs.begin() + address);
      }
    } else if (packet.code == scs::kWrite && !packet.params.empty()) {
      const std::size_t address = packet.params[0], length = packet.params.size() - 1;
      for (Servo& servo : servos_) {
        if (address + length <= scs::reg::kCount) {
          std::copy(packet.params.begin() + 1, packet.params.end(), servo.regs.begin() + address);
        }
      }
    }
    return;  // broadcasts are never answered
  }
  const std::size_t awaited = ReplyParams(packet);
  Servo* servo = Find(packet.id);
  if (!servo || (faults_on_ && Contains(config_.silent_ids, servo->id))) {
    Deliver(packet.id, awaited);  // no answer: the driver waits until its timeout
    return;
  }
  switch (packet.code) {
    case scs::kPing:
      Reply(*servo, 0, {}, awaited);
      return;
    case scs::kRead: {
      if (packet.params.size() != 2 || packet.params[0] + packet.params[1] > scs::reg::kCount) {
        Reply(*servo, scs::kErrorRange, {}, awaited);
        return;
      }
      const auto from = servo->regs.begin() + packet.params[0];
      Reply(*servo, 0, std::vector<std::uint8_t>(from, from + packet.params[1]), awaited);
      return;
    }
    case scs::kWrite: {
      if (packet.params.empty() || packet.params[0] + packet.params.size() - 1 > scs::reg::kCount) {
        Reply(*servo, scs::kErrorRange, {}, awaited);
        return;
      }
      std::copy(packet.params.begin() + 1, packet.params.end(),
                servo->regs.begin() + packet.params[0]);
      Reply(*servo, 0, {}, awaited);
      return;
    }
    default:
      Reply(*servo, scs::kErrorInstruction, {}, awaited);
      return;
  }
}

void SimServoBus::Reply(const Servo& servo, std::uint8_t error,
                        const std::vector<std::uint8_t>& params, std::size_t awaited_params) {
  // Called with mutex_ held (from Handle): unlocks it while writing what the
  // driver hears, and locks it again before returning.
  std::vector<std::uint8_t> bytes =
      scs::Encode({static_cast<std::uint8_t>(servo.id), error, params});
  double delay = config_.return_delay_s + config_.byte_time_s * bytes.size();
  if (faults_on_ && Contains(config_.slow_ids, servo.id)) delay += config_.slow_extra_s;
  for (std::uint8_t& b : bytes) {
    if (faults_on_ && config_.corrupt_probability > 0.0 &&
        rng_.Uniform() < config_.corrupt_probability) {
      b ^= static_cast<std::uint8_t>(1u << (rng_.Next() % 8));
      ++counters_.corrupted_bytes;
    }
  }
  const double due_s = wire_free_s_ + delay;
  wire_free_s_ = due_s;
  ++counters_.replies;
  pending_.push_back({due_s, servo.id, std::move(bytes)});
  Deliver(servo.id, awaited_params);
}

void SimServoBus::Deliver(int id, std::size_t params) {
  // What the driver hears before its reply timeout, in order, up to the reply
  // it accepts; it sends its next request then, or at the timeout.
  const double until_s = driver_s_ + servos_config_.reply_timeout_s;
  std::vector<std::uint8_t> heard;
  double answered_s = until_s;
  std::size_t arrived = 0;
  while (arrived < pending_.size() && pending_[arrived].due_s <= until_s) {
    const Pending& p = pending_[arrived++];
    heard.insert(heard.end(), p.bytes.begin(), p.bytes.end());
    if (AnswersRequest(p.bytes, id, params)) {
      answered_s = p.due_s;
      break;
    }
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(arrived));
  driver_s_ = answered_s;
  mutex_.unlock();
  const std::uint8_t* data = heard.data();
  std::size_t left = heard.size();
  while (left > 0) {
    const ssize_t n = ::write(pty_.master_fd(), data, left);
    if (n > 0) {
      data += n;
      left -= static_cast<std::size_t>(n);
    } else if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd p{pty_.master_fd(), POLLOUT, 0};
      ::poll(&p, 1, 10);
      if (!running_.load()) break;
    } else {
      break;
    }
  }
  mutex_.lock();
}

}  // namespace aerograsp
