// `aerograsp hardware-check --hardware CONFIG`: opens each device the
// hardware configuration names, on its own, and reports what answered. Nothing
// moves: the servos' torque is left off and the vehicle is not armed.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct HardwareCheckOptions {
  std::string config_path;  ///< hardware YAML (data/config/hardware_sim.yaml is the simulated one)
  std::uint64_t seed = 1;   ///< world seed for simulated devices
};

/// Returns the number of devices that could not be opened (0: all answer).
/// @throws ConfigError for a bad configuration file.
int RunHardwareCheck(const HardwareCheckOptions& options, std::ostream& out);

/// Adds `hardware-check`'s options to `cmd` (a CLI11 subcommand).
void AddHardwareCheckOptions(CLI::App* cmd, HardwareCheckOptions* options);

}  // namespace aerograsp
