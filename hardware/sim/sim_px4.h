// A simulated PX4 on the far end of a MAVLink 2 UDP link on loopback. It
// answers the commands the companion uses as PX4 does (arm / disarm,
// NAV_TAKEOFF with an AMSL altitude, NAV_LAND, DO_SET_MODE to AUTO.LOITER,
// AUTO.LAND or OFFBOARD, the last only while setpoints are streaming), with a
// COMMAND_ACK and, for refusals, a STATUSTEXT saying why; it forwards offboard
// setpoints to the simulated vehicle and publishes HEARTBEAT, SYS_STATUS,
// ATTITUDE, LOCAL_POSITION_NED and EXTENDED_SYS_STATE on the world's clock.
//
// Threading: incoming frames are served on the peer's thread, because the
// client blocks in a command until its COMMAND_ACK arrives and the owner (who
// would otherwise pump the peer) is that same blocked caller. The thread
// changes the vehicle only under the peer's lock; commands land while the
// client waits for their ACK, so at a definite simulated time, but an offboard
// setpoint may be applied just before or just after the owner's next step. The owner steps
// the world through StepWorld(), which takes the same lock and sends the
// telemetry that is due on the simulated clock.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "hardware/mavlink/mavlink_codec.h"
#include "hardware/mavlink/mavlink_link.h"
#include "hardware/mavlink/mavlink_messages.h"
#include "hardware/sim/world.h"

namespace aerograsp {

/// Faults of the simulated PX4, from faults_from_s of the simulated clock on.
struct SimPx4Faults {
  double faults_from_s{0.0};    ///< >= 0 s
  bool silent{false};           ///< the link is lost: nothing sent, everything ignored
  bool reject_commands{false};  ///< every COMMAND_LONG refused (TEMPORARILY_REJECTED)
};

struct SimPx4Config {
  int system_id{1};
  int component_id{1};
  double heartbeat_hz{2.0};       ///< (0, 100] Hz
  double telemetry_hz{50.0};      ///< ATTITUDE and LOCAL_POSITION_NED, (0, 1000] Hz
  double slow_telemetry_hz{5.0};  ///< EXTENDED_SYS_STATE and SYS_STATUS, (0, 100] Hz
  double home_amsl_m{0.0};  ///< AMSL altitude of the world origin (NAV_TAKEOFF param7 is AMSL), m
  double default_takeoff_m{2.5};  ///< take-off altitude when param7 is NaN (MIS_TAKEOFF_ALT), m
  double offboard_signal_s{0.5};  ///< OFFBOARD needs a setpoint this recent, s
  std::string signing_key_hex;    ///< when set: sign what it sends and accept only signed frames
  SimPx4Faults faults;
};

class SimPx4 {
 public:
  /// Binds 127.0.0.1 on a free UDP port and starts serving.
  /// @throws HardwareError when it cannot bind.
  SimPx4(World* world, const SimPx4Config& config);
  ~SimPx4();
  SimPx4(const SimPx4&) = delete;
  SimPx4& operator=(const SimPx4&) = delete;

  /// The UDP port the client sends to.
  int port() const { return link_.local_port(); }
  /// Owner's thread: World::Step(dt_s) under the peer's lock, then the telemetry due.
  void StepWorld(double dt_s);
  /// Link loss: sends nothing and ignores everything while silent.
  void SetSilent(bool silent) { silent_ = silent; }
  /// Loses the next `count` COMMAND_LONGs (tests the client's retries).
  void DropNextCommands(int count) { drop_commands_ = count; }
  std::int64_t commands_received() const { return commands_received_; }
  std::int64_t setpoints_received() const { return setpoints_received_; }
  /// Waits (wall clock, at most timeout_s) until `count` setpoints have been
  /// handled. A simulated run calls it after the client's turn so that each
  /// setpoint counts at the simulated time it was sent, however loaded the
  /// machine is. Returns false on timeout.
  bool WaitForSetpoints(std::int64_t count, double timeout_s) const;
  std::int64_t frames_rejected() const;
  /// When the configured faults first showed: the link fell silent, or the
  /// first command was refused (simulated time); < 0: not (yet).
  double first_fault_s() const { return first_fault_s_; }

 private:
  void Serve();
  void Handle(const mavlink::Frame& frame);
  void HandleCommand(const mavlink::CommandLong& command);
  void SendTelemetry(bool slow, bool heartbeat);
  template <class M>
  void Send(const M& message);

  World* world_;
  SimPx4Config config_;
  UdpLink link_;
  std::mutex send_mutex_;
  mavlink::Encoder encoder_;
  mavlink::Parser parser_;  // peer thread only
  std::mutex world_mutex_;
  double last_setpoint_s_ = -1e300;
  mavlink::SetPositionTargetLocalNed last_setpoint_;
  double next_fast_s_ = 0.0, next_slow_s_ = 0.0, next_heartbeat_s_ = 0.0;
  std::atomic<bool> silent_{false};
  std::atomic<bool> reject_commands_{false};
  std::atomic<double> first_fault_s_{-1.0};
  std::atomic<int> drop_commands_{0};
  std::atomic<std::int64_t> commands_received_{0}, setpoints_received_{0}, frames_rejected_{0};
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace aerograsp
