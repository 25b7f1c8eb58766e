// The hardware configuration (data/config/hardware_sim.yaml and
// hardware_example.yaml are the references): per device, which backend (real,
// or simulated through the same protocol, or simulated in-process) and its
// port, baud rate, IDs and calibration. Read by `aerograsp hardware-check`
// and `aerograsp mission --hardware`; hardware_factory.h builds the devices.
#pragma once

#include <string>

#include "hardware/device_health.h"
#include "hardware/mavlink/px4_autopilot.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/sim_px4.h"
#include "hardware/sim/sim_servo_bus.h"

namespace aerograsp {

struct ArmsHardwareConfig {
  /// "scs": the Feetech bus on `scs.port`; "sim-bus": the simulated SCS bus on a
  /// pseudo-terminal (the real driver, the simulated servos); "sim": in-process.
  std::string backend{"sim-bus"};
  ScsArmsConfig scs;          ///< ports, rates, ids and calibration (servos.* in the file)
  bool servos_given = false;  ///< false: ids and calibration are ScsArmsConfig::Default
  SimServoBusConfig sim_bus;  ///< timing and faults of "sim-bus"
};

struct AutopilotHardwareConfig {
  /// "px4": PX4 over MAVLink 2; "sim-px4": the simulated PX4 over UDP loopback
  /// (the real client, the simulated vehicle); "sim": in-process.
  std::string backend{"sim-px4"};
  Px4Config px4;
  SimPx4Faults sim_px4;  ///< faults of "sim-px4"
};

struct CameraHardwareConfig {
  /// "realsense": a D435 (needs a build with librealsense2); "replay": a sequence
  /// folder (or a .bag with librealsense2); "sim": the simulator's renderer.
  std::string backend{"sim"};
  std::string path;    ///< replay: sequence folder or .bag file
  std::string serial;  ///< realsense: device serial number; empty = the first one
  int width{640};      ///< realsense colour and aligned depth, pixels
  int height{480};
  int fps{30};
  SimCameraFaults sim;  ///< faults of "sim"
};

struct HardwareConfig {
  std::string source;                          ///< the file (for messages)
  std::string platform{"platform_4dof.yaml"};  ///< resolved against the file's folder
  std::string world{"world_default.yaml"};     ///< the simulated world, for simulated backends
  ArmsHardwareConfig arms;
  AutopilotHardwareConfig autopilot;
  CameraHardwareConfig camera;
  DeviceHealthLimits health;  ///< what the mission treats as a device fault

  /// Every device simulated in-process (no pseudo-terminal, no UDP): what the
  /// mission and the bench run without --hardware.
  static HardwareConfig InProcessSimulation(const std::string& platform_path,
                                            const std::string& world_path);
  /// True when any device is simulated (a World is needed).
  bool NeedsWorld() const;
  /// @throws ConfigError "<file>: <key>: ..." for a missing file, unknown key,
  /// wrong type, or a value Validate rejects.
  static HardwareConfig Load(const std::string& path);
  /// `source` is the file (Load passes `this->source`), `prefix` the key path
  /// of this tree in it, ending in "." ("" at the top). @throws ConfigError
  /// "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

}  // namespace aerograsp
