#include "app/calibration_hardware.h"

#include <fmt/format.h>

#include "core/config.h"
#include "core/data_dir.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {

void CheckCalibrationHardware(const HardwareConfig& config) {
  const std::string& f = config.source;
  if (config.camera.backend != "sim") {
    throw ConfigError(
        fmt::format("{}: camera.backend: '{}': the calibration wizard shows its board to the "
                    "simulated camera ('sim'); "
                    "{} is not supported yet",
                    f, config.camera.backend,
                    config.camera.backend == "replay"
                        ? "a recorded sequence cannot follow the poses the wizard plans, and "
                          "calibrating from a recording"
                        : "calibrating a real camera (a printed board on the real gripper or "
                          "held by hand)"));
  }
  if (config.arms.backend == "scs") {
    throw ConfigError(
        fmt::format("{}: arms.backend: 'scs' drives the real arms, but the camera and the board "
                    "are simulated: the wizard would "
                    "move real arms to show a board that only the simulated camera sees; use "
                    "'sim-bus' (the real driver, "
                    "simulated servos) or 'sim'",
                    f));
  }
  if (config.autopilot.backend == "px4") {
    throw ConfigError(fmt::format(
        "{}: autopilot.backend: 'px4' is a real vehicle, but the camera and the arms are "
        "simulated on the simulated vehicle; use 'sim-px4' or 'sim'",
        f));
  }
}

CalibrationHardware OpenCalibrationHardware(const std::string& hardware_path,
                                            const std::string& world_path, std::uint64_t seed) {
  CalibrationHardware hw;
  if (hardware_path.empty()) {
    const std::string world =
        world_path.empty() ? DataPath("config/world_default.yaml") : world_path;
    hw.config = HardwareConfig::InProcessSimulation(WorldConfig::Load(world).platform, world);
  } else {
    hw.config = HardwareConfig::Load(hardware_path);
    if (!world_path.empty()) hw.config.world = world_path;
  }
  CheckCalibrationHardware(hw.config);
  hw.devices = Hardware::Open(hw.config, seed);
  return hw;
}

}  // namespace aerograsp
