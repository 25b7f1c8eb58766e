// Device health during a mission: every servo cycle the servo bus (when the
// SCS driver runs) and the autopilot link, every grabbed frame the camera, and
// every answer to a command the vehicle legs send, through the checks of
// hardware/device_health.h with the hardware file's `health` bounds. The
// runner reacts to what it returns (a fault: arms to the safe state, vehicle
// holds); nothing here acts on a device.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hardware/device_health.h"
#include "hardware/hardware_factory.h"

namespace aerograsp {

class MissionHealth {
 public:
  /// `hw` must outlive this object.
  MissionHealth(Hardware* hw, const DeviceHealthLimits& limits);
  ~MissionHealth();
  MissionHealth(const MissionHealth&) = delete;
  MissionHealth& operator=(const MissionHealth&) = delete;

  /// Every servo cycle (`now_s` on the mission's clock): the faults found
  /// since the last poll, each (device, kind) once, refused commands included.
  std::vector<DeviceFault> Poll(double now_s);
  /// A frame the mission grabbed at `now_s`.
  std::vector<DeviceFault> Frame(double now_s, const RgbdFrame& frame);
  /// The mission wants no frames now.
  void CameraIdle() { health_.CameraIdle(); }
  /// The autopilot to command: forwards to the device and checks each answer.
  Autopilot* autopilot();
  /// Faults reported, by kind (DeviceFaultKindName).
  const std::map<std::string, int>& counts() const { return health_.counts(); }

 private:
  class CheckedAutopilot;
  Hardware* hw_;
  DeviceHealth health_;
  std::unique_ptr<CheckedAutopilot> autopilot_;
  std::vector<DeviceFault> refusals_;  // since the last poll
};

}  // namespace aerograsp
