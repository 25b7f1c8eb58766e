// The autopilot interface on PX4 over MAVLink 2 (docs/hardware.md, Autopilot).
// - Heartbeat out at heartbeat_hz; the autopilot's HEARTBEAT, ATTITUDE,
//   LOCAL_POSITION_NED, EXTENDED_SYS_STATE and STATUSTEXT in.
// - Commands as COMMAND_LONG, each waiting for its COMMAND_ACK with a timeout
//   and resent (confirmation counting up) up to command_attempts times.
// - Offboard: SetPositionTarget streams SET_POSITION_TARGET_LOCAL_NED at
//   setpoint_hz; before the first switch to OFFBOARD it streams for prestream_s
//   (PX4 refuses offboard without a live stream), then sends DO_SET_MODE.
// - Link loss: no heartbeat from the autopilot for link_timeout_s makes
//   VehicleState::link_ok false; the mission then stops the arms and holds
//   (a device fault, hardware/device_health.h, which also watches the age of
//   the newest state).
// Clocks: telemetry stamps, heartbeat / setpoint periods and the link timeout
// use the injected clock (the simulated one in simulation); waits for a
// COMMAND_ACK are I/O timeouts in real time.
// Threading: pump it with Spin() from the owner's loop (deterministic with a
// simulated clock), or StartThread() for a thread that spins at 100 Hz. The
// Autopilot methods are thread-safe; commands block until acknowledged.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "hardware/autopilot.h"
#include "hardware/mavlink/mavlink_codec.h"
#include "hardware/mavlink/mavlink_link.h"
#include "hardware/mavlink/mavlink_messages.h"

namespace aerograsp {

struct Px4Config {
  std::string link{"udp"};  ///< "udp" | "serial"
  std::string udp_local_host{"0.0.0.0"};
  int udp_local_port{14540};  ///< PX4 SITL sends to 14540; [0, 65535], 0 = any
  std::string udp_remote_host{"127.0.0.1"};
  int udp_remote_port{0};  ///< 0: answer whoever sends (PX4 SITL); [0, 65535]
  std::string serial_port{"/dev/ttyACM0"};
  int baud{921600};
  int system_id{1};               ///< ours, [1, 255] (same system as the vehicle)
  int component_id{191};          ///< ours: MAV_COMP_ID_ONBOARD_COMPUTER, [1, 255]
  int target_system{1};           ///< the autopilot's, [1, 255]
  int target_component{1};        ///< [1, 255]
  double heartbeat_hz{1.0};       ///< (0, 50] Hz
  double setpoint_hz{20.0};       ///< offboard stream, [10, 200] Hz (PX4 needs >= 2)
  double prestream_s{0.3};        ///< stream before switching to offboard, [0.1, 5] s
  double command_timeout_s{0.3};  ///< wait for a COMMAND_ACK, (0, 10] s
  int command_attempts{3};        ///< sends of a command before giving up, [1, 10]
  double link_timeout_s{1.0};     ///< no heartbeat for this long: link lost, (0, 60] s
  double connect_timeout_s{3.0};  ///< wait for the first heartbeat, (0, 120] s
  /// altitude of the take-off point above sea level (NAV_TAKEOFF wants AMSL), m
  double home_amsl_m{0.0};
  /// 64 hex digits: sign what we send and require signed frames; empty = off
  std::string signing_key_hex;
  int signing_link_id{0};  ///< [0, 255]
};

class Px4Autopilot : public Autopilot {
 public:
  using Clock = std::function<double()>;
  /// @throws HardwareError for a malformed signing key.
  Px4Autopilot(std::unique_ptr<MavlinkLink> link, const Px4Config& config, Clock clock);
  ~Px4Autopilot() override;
  Px4Autopilot(const Px4Autopilot&) = delete;
  Px4Autopilot& operator=(const Px4Autopilot&) = delete;

  /// Sends heartbeats and waits (real time) for the autopilot's first one.
  /// Call it before StartThread() (it reads the link itself).
  /// @throws HardwareError "autopilot (<link>): no heartbeat from system S component C within T s".
  void Connect();

  // Autopilot
  VehicleState State() const override;
  CommandAck Arm() override;
  CommandAck Disarm() override;
  CommandAck Takeoff(double altitude_m) override;
  CommandAck Land() override;
  CommandAck Hold() override;
  CommandAck SetPositionTarget(const Eigen::Vector3d& p_w, double yaw_rad) override;

  /// Receives everything waiting and sends what is due. The owner's loop calls
  /// it each cycle unless StartThread() runs.
  void Spin();
  void StartThread();
  void StopThread();

  bool link_ok() const;
  std::string Describe() const { return link_->Describe(); }
  mavlink::ParserCounters parser_counters() const;
  /// COMMAND_LONGs sent, retries included.
  std::int64_t commands_sent() const;
  /// SET_POSITION_TARGET_LOCAL_NED frames sent (the offboard stream).
  std::int64_t setpoints_sent() const { return setpoints_sent_; }

 private:
  struct Ack {
    std::uint8_t result = 0;
    std::int64_t serial = 0;  // which arrival
  };
  CommandAck Command(std::uint16_t command, const std::array<float, 7>& params, const char* name);
  /// Waits until an ACK of `command` newer than `after_serial` arrives or `timeout_s` (real)
  /// passes.
  bool WaitForAck(std::uint16_t command, std::int64_t after_serial, double timeout_s, Ack* ack);
  void ReceiveFor(double timeout_s);
  void Handle(const mavlink::Frame& frame);
  void SendDue(double now_s);
  void SendSetpoint();
  template <class M>
  void Send(const M& message);

  Px4Config config_;
  Clock clock_;
  std::unique_ptr<MavlinkLink> link_;
  std::mutex send_mutex_;
  mavlink::Encoder encoder_;
  mavlink::Parser parser_;  // only the receiving thread touches it

  mutable std::mutex mutex_;
  std::condition_variable ack_cv_;
  std::map<std::uint16_t, Ack> acks_;
  std::int64_t ack_serial_ = 0;
  std::int64_t commands_sent_ = 0;
  std::atomic<std::int64_t> setpoints_sent_{0};
  mavlink::ParserCounters counters_;
  bool armed_ = false;
  std::uint32_t custom_mode_ = 0;
  std::uint8_t landed_state_ = mavlink::kLandedUndefined;
  double last_heartbeat_s_ = -1e300;
  bool heard_ = false;
  VehicleState telemetry_;
  std::string last_status_text_;
  // Offboard stream.
  bool streaming_ = false;
  bool offboard_accepted_ = false;  // the switch was acknowledged
  bool offboard_seen_ = false;      // and a heartbeat has shown it since
  Eigen::Vector3d target_p_w_ = Eigen::Vector3d::Zero();
  double target_yaw_rad_ = 0.0;
  double last_setpoint_sent_s_ = -1e300;
  double last_heartbeat_sent_s_ = -1e300;

  std::thread thread_;
  std::atomic<bool> running_{false};
};

}  // namespace aerograsp
