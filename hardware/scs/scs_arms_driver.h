// Both arms and grippers on one Feetech SCS bus (docs/hardware.md, Servo bus).
// Each cycle: one SYNC_WRITE of goal position, time and speed (6 bytes from
// address 42) to every servo of both arms, then a READ of every present
// position, then the load, voltage and temperature of one servo (round robin,
// so each servo's status comes at rate / servo count).
// Safety: targets are clamped to the joint limits and to max_step_rad per
// cycle; when the newest target is older than stale_after_s the watchdog holds
// the last command sent (it never jumps home mid-grasp).
// Threading: Cycle() may be called by the owner (simulated clock, deterministic)
// or by the driver's own thread (StartThread, real time). The ArmsDriver
// methods are thread-safe. Time comes from the injected clock.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/platform.h"
#include "hardware/arms_driver.h"
#include "hardware/scs/scs_bus.h"
#include "hardware/scs/servo_calibration.h"

namespace aerograsp {

struct ScsArmsConfig {
  std::string port{"/dev/ttyUSB0"};  ///< serial device of the bus adapter
  int baud{1000000};                 ///< the SCS bus: 1 Mbaud
  double reply_timeout_s{0.005};     ///< wait for a status reply, (0, 1] s
  bool local_echo{false};            ///< the adapter echoes sent bytes (one-wire TTL boards)
  std::array<std::vector<ServoCalibration>, 2> joints;  ///< per side (left, right), one per joint
  std::array<GripperServoConfig, 2> grippers;           ///< per side
  /// Watchdog: hold when targets are older, (0, 10] s (0.2 s, as the original arms)
  double stale_after_s{0.2};
  /// Largest change of a command per cycle, (0, pi] rad (20 deg, as the original arms)
  double max_step_rad{0.349};
  int goal_time_ms{0};         ///< GOAL_TIME register, 0 = as fast as allowed, [0, 65535]
  int goal_speed{0};           ///< GOAL_SPEED register, 0 = maximum, [0, 65535]
  double rate_hz{100.0};       ///< cycle rate of the driver's thread, (0, 1000] Hz
  bool torque_on_start{true};  ///< enable torque after reading the start positions

  /// IDs 10*k + i (arm k = 1 left, 2 right, joint i from 1) and gripper 10*k + 7
  /// (docs/hardware.md); each joint's raw 0 at its lower limit and raw 1023 220 deg above
  /// it (the simulated servos' mapping, hardware/sim/world.h).
  static ScsArmsConfig Default(const Platform& platform);
};

/// What the driver knows of one servo.
struct ScsServoStatus {
  int id = 0;
  std::string name;       ///< "left j2", "right gripper"
  int raw_position = -1;  ///< last good PRESENT_POSITION; -1 before the first
  int load = 0;           ///< PRESENT_LOAD, signed (-1023 .. 1023)
  double voltage_v = 0.0;
  int temperature_c = 0;
  std::uint8_t error = 0;       ///< last status error bits
  int failed_reads = 0;         ///< consecutive failed reads (0 when healthy)
  std::int64_t good_reads = 0;  ///< position reads answered since the start
};

struct CycleReport {
  bool stale = false;    ///< the watchdog held the last command
  int failed_reads = 0;  ///< position reads that failed this cycle
  int late_replies = 0;  ///< replies of earlier exchanges that came this cycle (skipped)
  BusStatus sync_write = BusStatus::kOk;
};

class ScsArmsDriver : public ArmsDriver {
 public:
  using Clock = std::function<double()>;
  /// Opens the port, pings every servo, reads where they are (that becomes
  /// the held command) and enables torque (torque_on_start).
  /// @throws HardwareError "servo bus <port>: ..." naming the servos that do not answer.
  ScsArmsDriver(const Platform& platform, const ScsArmsConfig& config, Clock clock);
  ~ScsArmsDriver() override;
  ScsArmsDriver(const ScsArmsDriver&) = delete;
  ScsArmsDriver& operator=(const ScsArmsDriver&) = delete;

  // ArmsDriver (thread-safe).
  void SetJointTargets(Side side, const Eigen::VectorXd& q_rad) override;
  Eigen::VectorXd JointPositions(Side side) const override;
  void SetGripper(Side side, GripperCommand command) override;
  GripperState Gripper(Side side) const override;
  void Stop() override;

  /// One bus cycle. Not while the driver's thread runs.
  CycleReport Cycle();
  /// Runs Cycle() at rate_hz on a thread until StopThread() or destruction.
  void StartThread();
  void StopThread();
  /// Torque of every servo on or off (one SYNC_WRITE). Not while the driver's thread runs.
  BusStatus SetTorque(bool on);
  /// Torque of one arm's joint servos (its gripper keeps its own): off, a
  /// person can move the arm by hand. Not while the driver's thread runs.
  BusStatus SetTorque(Side side, bool on);

  std::vector<ScsServoStatus> servo_statuses() const;
  BusCounters counters() const;
  /// The commands last sent (rad), after limits and step limiting.
  Eigen::VectorXd last_command(Side side) const;

 private:
  struct ArmState {
    Eigen::VectorXd lower, upper;    // joint limits, rad
    Eigen::VectorXd target;          // newest target, clamped
    double target_stamp_s = -1e300;  // clock time of the newest target
    bool has_target = false;
    Eigen::VectorXd command;   // last sent
    Eigen::VectorXd measured;  // last read
    GripperCommand gripper = GripperCommand::kOpen;
    GripperState gripper_state;
    int gripper_last_raw = -1;
    double gripper_changed_s = 0.0;  // last time the gripper position changed
  };
  void UpdateGripperState(Side side, int raw, double now_s);
  std::size_t ServoIndex(Side side, int joint) const;  // into servos_

  ScsArmsConfig config_;
  Clock clock_;
  double max_aperture_m_;
  std::unique_ptr<ScsBus> bus_;
  mutable std::mutex mutex_;
  std::array<ArmState, 2> arms_;
  BusCounters counters_;                // copy of the bus's, taken each cycle
  std::vector<ScsServoStatus> servos_;  // left joints, left gripper, right joints, right gripper
  std::size_t next_status_ = 0;
  std::thread thread_;
  std::atomic<bool> running_{false};
};

}  // namespace aerograsp
