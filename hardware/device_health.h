// Device health: what counts as a faulty servo, servo bus, autopilot link or
// camera while the robot flies. The checks are pure functions of what the
// drivers report and of the bounds in the hardware file's `health` section;
// DeviceHealth keeps the little they need between cycles (when each reading
// last changed, the bus counters over the last window) and reports each fault
// of a device once. The mission polls it every servo cycle and, on a fault,
// stops the arms where they are and holds the vehicle (docs/reliability.md).
#pragma once

#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/image.h"
#include "hardware/autopilot.h"
#include "hardware/scs/scs_arms_driver.h"

namespace aerograsp {

/// The `health` section of a hardware file (data/config/hardware_example.yaml).
struct DeviceHealthLimits {
  int servo_max_failed_reads{3};          ///< failed reads of one servo in a row, [1, 100]
  double servo_max_reading_age_s{0.05};   ///< newest good position reading older, [0.005, 10] s
  double bus_max_error_rate{0.05};        ///< corrupted replies per exchange, [0, 1]
  double bus_error_window_s{0.1};         ///< ... over the exchanges of this window, [0.01, 10] s
  int bus_min_exchanges{20};              ///< the rate counts from this many exchanges, [1, 10000]
  double servo_min_voltage_v{6.0};        ///< supply range, [0, 30] V
  double servo_max_voltage_v{8.4};        ///< [min, 30] V
  double servo_max_temperature_c{70.0};   ///< hottest servo, [0, 120] C
  double autopilot_max_state_age_s{0.1};  ///< newest vehicle state older, [0.01, 60] s
  double camera_max_frame_age_s{0.07};  ///< no new frame while the mission wants one, [0.01, 10] s
  double camera_max_bad_depth_s{0.05};  ///< frames without one valid depth pixel, [0, 10] s

  /// `prefix` is the key path of this section in its file, ending in "."
  /// ("health." in a hardware file). @throws ConfigError
  /// "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

enum class DeviceFaultKind {
  kServoSilent,       ///< failed reads in a row
  kServoStale,        ///< no good reading for too long
  kBusCorrupt,        ///< corrupted replies above the rate (late ones are not)
  kServoVoltage,      ///< supply out of range
  kServoTemperature,  ///< too hot
  kLinkLost,          ///< the autopilot's state stopped coming
  kCommandRejected,   ///< the autopilot refused a command in flight
  kCameraNoFrame,     ///< no new frame
  kCameraBadDepth,    ///< no valid depth pixel
};
/// "servo_silent", "servo_stale", "bus_corrupt", "servo_voltage", "servo_temperature",
/// "link_lost", "command_rejected", "camera_no_frame", "camera_bad_depth".
const char* DeviceFaultKindName(DeviceFaultKind kind);

struct DeviceFault {
  DeviceFaultKind kind = DeviceFaultKind::kServoSilent;
  std::string device;  ///< "servo left j2 (id 12)", "servo bus", "autopilot", "camera"
  std::string what;    ///< "3 reads failed in a row"
  /// "device: what"
  std::string Text() const { return device + ": " + what; }
};

// ---- The checks -------------------------------------------------------------

/// One servo: failed reads, its newest good reading `reading_age_s` old,
/// voltage and temperature (checked once read: voltage_v > 0).
std::vector<DeviceFault> CheckServo(const ScsServoStatus& servo, double reading_age_s,
                                    const DeviceHealthLimits& limits);
/// The bus over a window: counters at its start and now.
std::optional<DeviceFault> CheckBusErrors(const BusCounters& from, const BusCounters& to,
                                          const DeviceHealthLimits& limits);
/// The autopilot link: the driver's link flag and the age of its newest state.
std::optional<DeviceFault> CheckAutopilotLink(const VehicleState& state, double state_age_s,
                                              const DeviceHealthLimits& limits);
/// A command's answer: a refusal is a fault once the vehicle is in the air
/// (on the ground the mission gives up instead: nothing flies yet).
std::optional<DeviceFault> CheckCommandAnswer(const std::string& command, const CommandAck& ack,
                                              FlightMode mode);
/// The camera: the newest new frame `frame_age_s` old, frames without valid
/// depth for `bad_depth_for_s` (< 0: the last frame had depth).
std::vector<DeviceFault> CheckCamera(double frame_age_s, double bad_depth_for_s,
                                     const DeviceHealthLimits& limits);
/// True when any pixel of a depth image holds a measurement (0 is "no data").
bool DepthHasData(const DepthImage& depth);

// ---- The monitor --------------------------------------------------------------

/// Feeds the checks. Times are the caller's clock (seconds); each fault of a
/// (device, kind) is returned once.
class DeviceHealth {
 public:
  explicit DeviceHealth(const DeviceHealthLimits& limits) : limits_(limits) {}

  /// The servo bus's statuses and counters, every cycle.
  std::vector<DeviceFault> Servos(double now_s, const std::vector<ScsServoStatus>& servos,
                                  const BusCounters& counters);
  /// The autopilot's state, every cycle.
  std::vector<DeviceFault> Autopilot(double now_s, const VehicleState& state);
  /// A command's answer.
  std::vector<DeviceFault> CommandAnswered(const std::string& command, const CommandAck& ack,
                                           FlightMode mode);
  /// A frame the mission grabbed: its stamp and whether its depth has data.
  std::vector<DeviceFault> Frame(double now_s, double stamp_s, bool depth_has_data);
  /// The mission does not want frames: the frame age restarts at the next one.
  void CameraIdle() { camera_idle_ = true; }

  /// Faults reported so far, by DeviceFaultKindName.
  const std::map<std::string, int>& counts() const { return counts_; }

 private:
  std::vector<DeviceFault> Report(std::vector<DeviceFault> faults);

  DeviceHealthLimits limits_;
  std::map<int, std::pair<std::int64_t, double>> servo_reads_;  // id: good reads, when changed
  std::deque<std::pair<double, BusCounters>> bus_window_;
  double state_stamp_s_ = -1e300, state_changed_s_ = 0.0;
  bool state_seen_ = false;
  bool camera_idle_ = true;
  double frame_stamp_s_ = -1e300, frame_new_s_ = 0.0, bad_depth_since_s_ = -1.0;
  std::set<std::pair<std::string, DeviceFaultKind>> reported_;
  std::map<std::string, int> counts_;
};

}  // namespace aerograsp
