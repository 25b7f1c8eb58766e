// The devices the calibration wizards drive: the built-in simulation by
// default, or what a hardware configuration names (`--hardware CONFIG`), the
// way `aerograsp bench --hardware` opens them. The wizards show the board in
// the simulated world, so they need the simulated camera; configurations they
// cannot drive are refused with the reason instead of faked.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "hardware/hardware_config.h"
#include "hardware/hardware_factory.h"

namespace aerograsp {

struct CalibrationHardware {
  HardwareConfig config;  ///< what was opened (source: the file or "built-in simulation")
  std::unique_ptr<Hardware> devices;  ///< its world() is never null
};

/// Checks that the wizards can drive `config`: the simulated camera ('sim'),
/// simulated arms ('sim' or 'sim-bus', the real SCS driver on the simulated
/// bus) and a simulated autopilot ('sim' or 'sim-px4').
/// @throws ConfigError "<file>: <key>: '<backend>': <why>, <what to use>".
void CheckCalibrationHardware(const HardwareConfig& config);

/// Loads `hardware_path` (empty: every device in-process in `world_path`, or
/// data/config/world_default.yaml when that is empty too; a `world_path` given
/// with a hardware file replaces the file's world), checks it and opens it.
/// @throws ConfigError / HardwareError naming the file, the key or the device.
CalibrationHardware OpenCalibrationHardware(const std::string& hardware_path,
                                            const std::string& world_path, std::uint64_t seed);

}  // namespace aerograsp
