// The devices the calibration wizards drive: the built-in simulation by
// default, or what a hardware configuration names (`--hardware CONFIG`).
//
// The hand-eye wizard (OpenHandEyeHardware) runs on the real bus and camera
// ('scs' + 'realsense') or on simulated ones ('sim' / 'sim-bus' + 'sim'): the
// board must really be in front of the camera used, so a real camera with
// simulated arms (or the reverse) is refused. The rig (which board, where it
// is fixed) is the `calibration` section of the hardware file
// (CalibrationRig); a simulated world is built carrying the board where that
// section says, so the wizard's code is the same on the robot and in tests.
//
// The intrinsics wizard opens only the camera (app/calibration/calibrate_intrinsics.h:
// OpenIntrinsicsHardware) and reads its limits from the same section.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "calib/coverage.h"
#include "calib/tag_board.h"
#include "core/platform.h"
#include "hardware/hardware_config.h"
#include "hardware/hardware_factory.h"
#include "telemetry/telemetry.h"

namespace aerograsp {

class World;
class SimServoBus;
class ScsArmsDriver;

/// The `calibration` section of a hardware file: the rig and the wizard's
/// limits (data/config/hardware_example.yaml documents each with its unit).
struct CalibrationRig {
  std::string source;            ///< the hardware file (for messages)
  std::string mount{"gripper"};  ///< "gripper": on the calibrated arm's gripper; "hand": held
  TagBoardConfig board;          ///< the printed board
  Eigen::Isometry3d eMt = Eigen::Isometry3d::Identity();  ///< board in the tool frame (gripper)
  double joint_speed_deg_s{30.0};    ///< joint speed while calibrating, (0, 180] deg/s
  double settle_timeout_s{3.0};      ///< longest wait for an arm to settle, (0, 60] s
  double settle_tolerance_deg{0.5};  ///< settled: every joint this close to its target, deg
  double settle_window_s{0.2};       ///< ... with readings unchanged for this long, s
  double min_voltage_v{6.0};         ///< servo supply range, V
  double max_voltage_v{8.4};
  double max_temperature_c{60.0};  ///< hottest servo allowed, deg C
  int max_failed_reads{3};         ///< consecutive failed reads of a servo that stop the run
  /// Hand-held intrinsics: the board is still when no corner moved more than this
  /// since the previous frame, [0.01, 20] px.
  double still_px{1.0};
  /// Hand-held intrinsics: frames in a row the camera may fail to deliver, [1, 1000].
  int max_missed_frames{30};
  /// Hand-held intrinsics: the image cells and board tilts the samples must
  /// cover before the wizard solves (`calibration.coverage`).
  CoverageConfig coverage;

  /// The defaults when the file has no `calibration` section.
  /// @throws ConfigError "<file>: calibration.<key>: ..." for unknown keys and bounds.
  static CalibrationRig Load(const std::string& hardware_path);
  /// `prefix` is the key path of this section in its file, ending in "." ("calibration." in
  /// a hardware file). @throws ConfigError "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// Opened devices of a hand-eye run. On the robot world() is null and time is
/// the steady clock; simulated, Wait() steps the world on its clock.
class HandEyeHardware {
 public:
  ~HandEyeHardware();
  HandEyeHardware(const HandEyeHardware&) = delete;
  HandEyeHardware& operator=(const HandEyeHardware&) = delete;

  const HardwareConfig& config() const { return config_; }
  const CalibrationRig& rig() const { return rig_; }
  const Platform& platform() const { return *platform_; }
  World* world() { return world_.get(); }
  RgbdCamera& camera() { return *camera_; }
  ArmsDriver& arms() { return *arms_; }
  /// The SCS driver when the arms are on a bus (real or simulated), else null.
  ScsArmsDriver* scs() { return scs_; }
  /// "scs on /dev/ttyUSB0", "simulated SCS bus on /dev/pts/3", "in-process simulator".
  std::string ArmsWhere() const;

  /// Seconds on the run's clock.
  double now_s() const;
  /// Lets dt_s pass: simulated, one bus cycle, the bus's sync and a world
  /// step; on the robot, a sleep while the driver's thread runs the bus.
  void Wait(double dt_s);
  /// Torque on (but for the `limp` arm's joints, which a person then moves by
  /// hand) and, on the robot, the driver's bus thread started: from now on the arms move.
  void Arm(std::optional<Side> limp = std::nullopt);
  /// Torque back on for `side`, holding where the arm stands (no jump).
  void Stiffen(Side side);
  /// From now on each Wait tells `sink` (may be null; must outlive the
  /// hardware) both arms' joints and tools.
  void SetTelemetry(TelemetrySink* sink) { telemetry_ = sink; }
  TelemetrySink* telemetry() const { return telemetry_; }
  /// From now on the wizard polls `source` (may be null; must outlive the
  /// hardware) at each of its steps: a stop ends the run as Ctrl-C does (both
  /// arms stop, the samples are kept); the source's notes go to `note`.
  void SetEmergencyStop(EmergencyStopSource* source,
                        std::function<void(const std::string&)> note = {}) {
    emergency_stop_ = source;
    emergency_note_ = std::move(note);
  }
  /// The stop requested through the source set by SetEmergencyStop, if any:
  /// "emergency stop from <source>: <reason>"; "" when none (notes said).
  std::string PollEmergencyStop();

 private:
  friend std::unique_ptr<HandEyeHardware> OpenHandEyeHardware(const std::string&,
                                                              const std::string&, std::uint64_t,
                                                              Side, std::ostream&);
  HandEyeHardware() = default;
  HardwareConfig config_;
  CalibrationRig rig_;
  std::unique_ptr<World> world_;
  std::unique_ptr<Platform> platform_;
  std::unique_ptr<SimServoBus> sim_bus_;
  std::unique_ptr<RgbdCamera> camera_;
  std::unique_ptr<ArmsDriver> arms_;
  ScsArmsDriver* scs_ = nullptr;
  TelemetrySink* telemetry_ = nullptr;
  EmergencyStopSource* emergency_stop_ = nullptr;
  std::function<void(const std::string&)> emergency_note_;
};

/// Loads `hardware_path` (empty: every device in-process in `world_path`, or
/// data/config/world_default.yaml, with the default rig) and its rig, checks
/// the mix of backends, builds the simulated world when one is needed (with
/// the board on the `side` gripper when the rig says so), then opens the arms
/// (torque left as it is) and the camera, printing one line per device on
/// `out`. Every device is tried.
/// @throws ConfigError for a refused mix or a bad rig; HardwareError naming each
/// device that did not open, with its port ("arms: servo bus /dev/ttyUSB0: ...").
std::unique_ptr<HandEyeHardware> OpenHandEyeHardware(const std::string& hardware_path,
                                                     const std::string& world_path,
                                                     std::uint64_t seed, Side side,
                                                     std::ostream& out);

/// The pre-flight checks before anything moves: every servo answers with its
/// voltage and temperature in range and no error bits, each arm's servo count
/// is its URDF's, every joint reads inside its URDF limits, the camera streams
/// a frame of its intrinsics' size. Prints one line per check on `out`.
/// Returns the failures (empty: all passed) and the frame grabbed.
std::vector<std::string> PreflightDevices(HandEyeHardware& hw, RgbdFrame* frame, std::ostream& out);

}  // namespace aerograsp
